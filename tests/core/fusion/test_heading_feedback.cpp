// The heading state's parts (issue 11, part 2): the feedback of a well-determined yaw
// offset into the AHRS with its PI bias loop, the EKF path's scalar observer, the AHRS's
// correction entry point, and the particle filter's per-particle yaw offset.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/filter/particle_filter.hpp"
#include "core/fusion/heading_feedback.hpp"
#include "core/imu/mahony_filter.hpp"

using namespace luxloc;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr TimeNs kFrame = 33'333'333;  // 30 fps
}  // namespace

TEST_CASE("HeadingFeedback learns a residual gyro z bias from the offsets that keep coming back", "[heading]") {
  HeadingFeedback fb;
  const double bias = 0.5 * kDeg;  // rad/s the AHRS does not integrate
  double learnt = 0.0;
  // The AHRS drifts at (bias - learnt) between frames; each frame's offset is that drift.
  for (int k = 0; k < 30 * 60; ++k) {
    const double offset = (bias - learnt) * ns_to_seconds(kFrame);
    const auto tr = fb.update(k * kFrame, offset, 0.2 * kDeg);
    REQUIRE(tr);
    CHECK(tr->dyaw_rad == Approx(offset));
    learnt += tr->drate_rps;
  }
  // Time constant bias_tau_s (8 s): after a minute (7.5 tau) within 0.1 % of the bias.
  CHECK(learnt == Approx(bias).epsilon(0.01));
  CHECK(fb.learnt_rate_rps() == Approx(learnt));
  CHECK(fb.transfers() == 30u * 60u);
}

TEST_CASE("HeadingFeedback: no transfer of a poorly known offset, no bias from the first or a late transfer",
          "[heading]") {
  HeadingFeedback fb;
  CHECK_FALSE(fb.update(0, 0.1, 5.0 * kDeg));        // sigma beyond max_sigma_rad
  CHECK_FALSE(fb.update(0, std::nan(""), 0.001));    // NaN never reaches the AHRS
  const auto first = fb.update(0, 0.2, 0.5 * kDeg);  // the alignment error at start: not a rate
  REQUIRE(first);
  CHECK(first->dyaw_rad == Approx(0.2));
  CHECK(first->drate_rps == 0.0);
  const auto late = fb.update(5'000'000'000, 0.05, 0.5 * kDeg);  // 5 s later: a gap's offset
  REQUIRE(late);
  CHECK(late->drate_rps == 0.0);
  // A big offset 33 ms after a transfer counts only up to max_rate_rps of drift.
  const auto jump = fb.update(5'000'000'000 + kFrame, 0.3, 0.5 * kDeg);
  REQUIRE(jump);
  CHECK(std::abs(jump->drate_rps) <= 0.035 * ns_to_seconds(kFrame) / 8.0 + 1e-12);
  CHECK(fb.since_fix_s(6'000'000'000 + kFrame) == Approx(1.0));
  // max_step_rad caps one correction.
  const auto huge = fb.update(6'000'000'000, 2.0, 0.5 * kDeg);
  REQUIRE(huge);
  CHECK(huge->dyaw_rad == Approx(0.35));
}

TEST_CASE("HeadingObserver: camera yaw shrinks its sigma, an outlier is gated, drift grows it", "[heading]") {
  HeadingObserver h;
  CHECK(h.sigma_rad() == Approx(0.10));
  REQUIRE(h.correct({0, 0.03, 0.005}));
  CHECK(h.offset_rad() == Approx(0.03).margin(0.001));
  CHECK(h.sigma_rad() < 0.008);
  for (int i = 0; i < 100; ++i) h.correct({0, 0.03, 0.005});
  CHECK(h.sigma_rad() == Approx(0.005));  // the floor: repeated camera yaws share errors
  CHECK_FALSE(h.correct({0, 0.5, 0.005}));  // 0.47 rad off at sigma 0.007: refused
  CHECK(h.rejected() == 1u);
  const double s0 = h.sigma_rad();
  h.predict(15.0, 0.0);  // 15 s, the drift clock at 0: only the white walk
  const double s_walk = h.sigma_rad();
  HeadingObserver g;
  g.correct({0, 0.03, 0.005});
  g.predict(15.0, 30.0);  // 30 s since the last fix: the residual bias's drift dominates
  CHECK(s_walk > s0);
  CHECK(g.sigma_rad() > 2.0 * s_walk);
  h.shift(0.03);
  CHECK(h.offset_rad() == Approx(0.0).margin(0.001));
}

TEST_CASE("MahonyFilter::correct_heading turns the yaw only and moves the vertical gyro bias", "[heading][imu]") {
  MahonyFilter f;
  ImuSample s;
  s.acc_inB = {0.0, 0.0, 9.80665};
  s.gyro_inB = Eigen::Vector3d::Zero();
  s.t = 0;
  f.update(s);
  REQUIRE(f.initialized());
  const double roll0 = f.roll(), pitch0 = f.pitch(), yaw0 = f.yaw();
  f.correct_heading(10.0 * kDeg, 0.0);
  CHECK(f.yaw() == Approx(yaw0 + 10.0 * kDeg));
  CHECK(f.roll() == Approx(roll0).margin(1e-9));
  CHECK(f.pitch() == Approx(pitch0).margin(1e-9));
  // drate: the AHRS now integrates 1 deg/s more about the vertical (body z is up here).
  f.correct_heading(0.0, 1.0 * kDeg);
  CHECK(f.gyro_bias().z() == Approx(-1.0 * kDeg));
  f.correct_heading(std::nan(""), 0.0);  // ignored
  CHECK(std::isfinite(f.yaw()));
}

TEST_CASE("Particle filter: the yaw offset state is weighed, estimated and shifted", "[heading][pf]") {
  ParticleFilterOptions o;
  o.particles = 4000;
  o.seed = 7;
  ParticleFilter pf(o);
  pf.initialize({1.0, 2.0}, Eigen::Matrix2d::Identity() * 0.01);
  REQUIRE(pf.has_heading());
  ParticleFilter::HeadingEstimate h0 = pf.heading_estimate();
  REQUIRE(h0.valid);
  CHECK(h0.sigma_rad == Approx(o.heading.sigma0_rad).epsilon(0.05));  // the prior
  // A likelihood that sees the yaw offset only: e ~ N(0.04, 0.01^2).
  REQUIRE(pf.weigh([](double, double, double e) { return -0.5 * (e - 0.04) * (e - 0.04) / 1e-4; }));
  const ParticleFilter::HeadingEstimate h1 = pf.heading_estimate();
  CHECK(h1.offset_rad == Approx(0.04).margin(0.003));
  CHECK(h1.sigma_rad == Approx(0.01).margin(0.002));
  pf.shift_heading(0.04);
  CHECK(pf.heading_estimate().offset_rad == Approx(0.0).margin(0.003));
  // Predictions add the walk (deferred until the next estimate): the spread grows.
  MotionInput u(1.0);
  u.heading_drift_s = 10.0;
  for (int i = 0; i < 10; ++i) pf.predict(u);
  CHECK(pf.heading_estimate().sigma_rad > 2.0 * h1.sigma_rad);
  // A two-argument likelihood still works and leaves the offsets alone.
  REQUIRE(pf.weigh([](double x, double) { return -x * x; }));
  // Disabled: no state, estimate invalid.
  o.heading.enabled = false;
  ParticleFilter plain(o);
  plain.initialize({0.0, 0.0}, Eigen::Matrix2d::Identity());
  CHECK_FALSE(plain.has_heading());
  CHECK_FALSE(plain.heading_estimate().valid);
}
