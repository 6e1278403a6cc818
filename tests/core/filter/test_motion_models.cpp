// The motion models of the planar filters (core/filter/motion_model.hpp): the pedestrian
// model's gait calibration (step-length scale, heading offset) learnt from fixes carries
// the dead reckoning through an outage, in the particle filter and in the EKF alike.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>
#include <tbb/global_control.h>

#include "core/filter/ekf_filter.hpp"
#include "core/filter/fast_rng.hpp"
#include "core/filter/motion_model.hpp"
#include "core/filter/particle_filter.hpp"

using namespace luxloc;

namespace {

// A walker on a 4 m circle at 1.2 m/s. Its PDR reports a speed 1/0.9 too high (step-length
// scale 0.9) and a heading 0.06 rad too small (heading offset +0.06); fixes (3 cm) at 10 Hz
// for `fixes_s`, then none for `outage_s`. Returns the position error at the end.
struct Outcome {
  double err_end_m = 0.0;
  double max_err_outage_m = 0.0;
};

constexpr double kSpeed = 1.2, kRadius = 4.0, kScale = 0.9, kOffset = 0.06;

Outcome walk(PlanarFilter& f, double fixes_s = 30.0, double outage_s = 15.0) {
  const double dt = 0.01;
  Eigen::Vector2d p(kRadius, 0.0);
  f.initialize(p, Eigen::Matrix2d::Identity() * 0.01);
  FastRng noise(5);
  Outcome o;
  const int n = static_cast<int>((fixes_s + outage_s) / dt);
  for (int k = 1; k <= n; ++k) {
    const double t = k * dt;
    const double heading = M_PI / 2 + kSpeed / kRadius * (t - 0.5 * dt);  // true heading over the step
    p += kSpeed * dt * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    MotionInput u;
    u.dt = dt;
    u.has_gait = true;
    u.gait.speed_mps = kSpeed / kScale;
    u.gait.heading_rad = heading - kOffset;
    u.gait.length_sigma_m = 0.05 * 0.67;
    u.gait.heading_sigma_rad = 0.035;
    u.gait.step_period_s = 0.55;
    f.predict(u);
    if (t <= fixes_s && k % 10 == 0) {
      PositionMeasurement m;
      m.z = p + 0.03 * Eigen::Vector2d(noise.normal(), noise.normal());
      m.R = Eigen::Matrix2d::Identity() * 0.03 * 0.03;
      f.correct(m);
    }
    const PlanarEstimate e = f.estimate();
    REQUIRE(e.valid);
    const double err = (e.p - p).norm();
    if (t > fixes_s) o.max_err_outage_m = std::max(o.max_err_outage_m, err);
    o.err_end_m = err;
  }
  return o;
}

}  // namespace

TEST_CASE("Particle filter, pedestrian model: the fixes calibrate step length and heading offset", "[filter][motion]") {
  ParticleFilterOptions opt;
  opt.particles = 5000;
  ParticleFilter pf(opt);
  const Outcome o = walk(pf);
  const ParticleFilter::GaitEstimate g = pf.gait_estimate();
  REQUIRE(g.valid);
  // Position fixes see the walking direction only: the gait offset d plus the yaw-offset
  // state e (heading_noise.hpp) together; which of the two holds it they cannot tell.
  const double walk_offset = g.heading_offset_rad + pf.heading_estimate().offset_rad;
  INFO("scale " << g.scale << " +- " << g.scale_sigma << ", offset d + e " << walk_offset << " (d "
                << g.heading_offset_rad << " +- " << g.heading_offset_sigma << "); outage: max " << o.max_err_outage_m
                << " m, end " << o.err_end_m);
  CHECK(g.scale == Approx(kScale).margin(0.03));
  CHECK(walk_offset == Approx(kOffset).margin(0.02));
  // 18 m of dead reckoning through the outage with the calibrated gait.
  CHECK(o.max_err_outage_m < 0.5);

  // Without calibration states (no prior spread, no walk) the same outage ends far off.
  ParticleFilterOptions fixed = opt;
  fixed.gait.scale_sigma0 = fixed.gait.heading_offset_sigma0 = 0.0;
  fixed.gait.scale_walk = fixed.gait.heading_offset_walk = 0.0;
  fixed.heading.enabled = false;  // nor the yaw-offset state, which would take the offset up
  ParticleFilter pf_fixed(fixed);
  const Outcome uncal = walk(pf_fixed);
  INFO("uncalibrated: max " << uncal.max_err_outage_m << " m");
  CHECK(uncal.max_err_outage_m > 3.0 * o.max_err_outage_m);
}

TEST_CASE("EKF, pedestrian model: the same calibration through its Jacobian", "[filter][motion]") {
  EkfFilter ekf;
  const Outcome o = walk(ekf);
  const auto& x = ekf.full_state();
  INFO("scale " << x(4) << ", offset " << x(5) << "; outage: max " << o.max_err_outage_m << " m");
  CHECK(x(4) == Approx(kScale).margin(0.03));
  CHECK(x(5) == Approx(kOffset).margin(0.02));
  CHECK(o.max_err_outage_m < 0.5);
  CHECK(ekf.covariance().allFinite());
}

TEST_CASE("Pedestrian model: bit-identical across thread counts, resampling keeps the gait states", "[filter][motion]") {
  ParticleFilterOptions opt;
  opt.particles = 20000;  // several chunks
  auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    ParticleFilter pf(opt);
    walk(pf, 3.0, 1.0);
    return pf;
  };
  const ParticleFilter a = run(1), b = run(2);
  REQUIRE(a.particles().gait);
  REQUIRE(a.particles().ks.size() == a.size());
  CHECK(a.resample_count() > 0);
  bool same = true;
  for (std::size_t i = 0; i < a.size(); ++i)
    same = same && a.particles().x[i] == b.particles().x[i] && a.particles().ks[i] == b.particles().ks[i] &&
           a.particles().dpsi[i] == b.particles().dpsi[i];
  CHECK(same);
}

TEST_CASE("Pedestrian model: non-finite gait inputs predict nothing, standing still does not drift", "[filter][motion]") {
  for (const bool particle : {true, false}) {
    std::unique_ptr<PlanarFilter> f;
    if (particle)
      f = std::make_unique<ParticleFilter>();
    else
      f = std::make_unique<EkfFilter>();
    f->initialize({1.0, 2.0}, Eigen::Matrix2d::Identity() * 0.01);
    MotionInput u;
    u.dt = 0.01;
    u.has_gait = true;
    u.gait.speed_mps = NAN;
    f->predict(u);
    u.gait.speed_mps = 1.0;
    u.gait.heading_rad = INFINITY;
    f->predict(u);
    PlanarEstimate e = f->estimate();
    REQUIRE(e.valid);
    CHECK((e.p - Eigen::Vector2d(1.0, 2.0)).norm() < 0.01);
    // 60 s standing: speed 0, no per-step noise; only the small diffusion floor.
    u.gait = GaitInput{};
    for (int k = 0; k < 6000; ++k) f->predict(u);
    e = f->estimate();
    REQUIRE(e.valid);
    CHECK((e.p - Eigen::Vector2d(1.0, 2.0)).norm() < 0.05);
    CHECK(e.v.norm() < 1e-6);
    CHECK(std::sqrt(e.cov_p.trace()) < 0.3);
  }
}

TEST_CASE("Motion model names parse and print", "[filter][motion]") {
  for (const std::string& n : motion_model_names()) CHECK(to_string(parse_motion_model(n)) == n);
  CHECK_THROWS_AS(parse_motion_model("walk"), std::invalid_argument);
}

// The fusion's hooks at an outage (docs/MOTION.md "Gait fitted to the track"): shift_gait
// re-centres k and the turn slowdown keeping the spread; decouple_heading shuffles the yaw offsets (and,
// asked to, the walking-direction offsets), keeping their spread, so that the first fix after
// the dark cannot pick them by the position they turned each particle to.
TEST_CASE("Pedestrian model: the gait re-centred, the heading offsets cut from the positions", "[filter][motion][gait]") {
  ParticleFilterOptions opt;
  opt.particles = 4000;
  ParticleFilter pf(opt);
  walk(pf, 30.0, 0.0);
  // The dark, 15 s, with the offsets' spread widened as the fusion does at an outage: each
  // particle's d + e turns its track.
  pf.widen_gait(0.05, 0.15);  // d: 0.15 rad, so that it, not the step noise, spreads the tracks
  for (int k = 3001; k <= 4500; ++k) {
    const double dt = 0.01, t = k * dt;
    MotionInput u;
    u.dt = dt;
    u.has_gait = true;
    u.gait.speed_mps = kSpeed / kScale;
    u.gait.heading_rad = M_PI / 2 + kSpeed / kRadius * (t - 0.5 * dt) - kOffset;
    u.gait.length_sigma_m = 0.05 * 0.67;
    u.gait.heading_sigma_rad = 0.035;
    u.gait.step_period_s = 0.55;
    pf.predict(u);
  }
  const std::size_t n = pf.size();
  const auto offsets = [&] {
    std::vector<double> e(n), d(n);
    for (std::size_t i = 0; i < n; ++i) e[i] = pf.yaw_offset(i), d[i] = pf.gait_offset(i);
    return std::make_pair(e, d);
  };
  // A walking-direction offset delta turns the dark's displacement c by delta: the particle
  // ends delta R90 c off. c: the true chord of the circle from 30 s to 45 s.
  const double w = kSpeed / kRadius;
  const Eigen::Vector2d c = kRadius * Eigen::Vector2d(std::cos(45.0 * w) - std::cos(30.0 * w), std::sin(45.0 * w) - std::sin(30.0 * w));
  const Eigen::Vector2d across = Eigen::Vector2d(-c.y(), c.x()).normalized();
  const auto offset_position_correlation = [&] {
    // Correlation of the walking-direction offset d + e with the position across the chord.
    double se = 0, sp = 0, see = 0, spp = 0, sep = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = pf.yaw_offset(i) + pf.gait_offset(i), p = pf.position(i).dot(across);
      se += e, sp += p, see += e * e, spp += p * p, sep += e * p;
    }
    const double m = static_cast<double>(n), cov = sep / m - se / m * sp / m;
    const double ve = see / m - se / m * se / m, vp = spp / m - sp / m * sp / m;
    return std::abs(cov / std::sqrt(ve * vp));
  };
  const auto [e0, d0] = offsets();
  pf.decouple_heading(false);  // the yaw offsets only: d stays with its particle
  const auto [e1, d1] = offsets();
  CHECK(d1 == d0);
  CHECK(e1 != e0);
  auto se0 = e0, se1 = e1;
  std::sort(se0.begin(), se0.end());
  std::sort(se1.begin(), se1.end());
  CHECK(se1 == se0);  // the same offsets, only their owners changed
  const double corr_before = offset_position_correlation();
  pf.decouple_heading(true);
  const double corr_after = offset_position_correlation();
  WARN("walking-direction offset - position correlation " << corr_before << " -> " << corr_after);
  CHECK(corr_before > 0.3);
  CHECK(corr_after < 0.1);

  const ParticleFilter::GaitEstimate g = pf.gait_estimate();
  REQUIRE(g.valid);
  pf.shift_gait(0.05, 0.01);
  const ParticleFilter::GaitEstimate s = pf.gait_estimate();
  CHECK(s.scale == Approx(g.scale + 0.05).margin(1e-4));
  CHECK(s.scale_sigma == Approx(g.scale_sigma).margin(1e-4));
  CHECK(s.turn_slowdown_m_per_rad == Approx(g.turn_slowdown_m_per_rad + 0.01).margin(1e-3));
  pf.shift_gait(std::numeric_limits<double>::quiet_NaN(), 0.0);  // ignored
  CHECK(pf.gait_estimate().scale == Approx(s.scale).margin(1e-9));
}
