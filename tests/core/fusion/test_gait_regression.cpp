// The gait fitted to the tracked stretches (core/fusion/gait_regression.cpp, issue 12:
// dead reckoning through an outage with a calibrated gait).
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "core/fusion/gait_regression.hpp"

using namespace luxloc;

namespace {

TimeNs at(double s) { return static_cast<TimeNs>(std::llround(s * 1e9)); }

// A walker on a loop of 6 s straights and 2 s quarter turns (|omega| = pi / 4 rad/s), whose
// step model says 1.2 m/s; the true speed is k times that less A |omega| (A = 0.2 m lost per
// radian turned, GaitNoise::turn_slowdown0; the gait pays out |omega|). The filter's
// position is the truth plus 2 cm of noise (what VLC fixes give) while `tracking(t)`.
struct Walker {
  double k = 0.85, slowdown = 0.2, speed = 1.2;
  template <class Tracking>
  void walk(GaitRegression& r, double t0, double t1, Tracking tracking, std::uint64_t seed = 3,
            Eigen::Vector2d jump_at_40 = Eigen::Vector2d::Zero()) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, 0.02);
    const double dt = 0.01;
    for (double t = t0; t < t1; t += dt) {
      const double phase = std::fmod(t, 8.0);
      const double omega = phase >= 6.0 ? std::numbers::pi / 4.0 : 0.0;
      heading += omega * dt;
      const Eigen::Vector2d u(std::cos(heading), std::sin(heading));
      p += (k * speed - slowdown * omega) * dt * u;
      r.add_motion(speed, omega, u, dt);
      Eigen::Vector2d seen = p + Eigen::Vector2d(n(rng), n(rng));
      if (t >= 40.0) seen += jump_at_40;
      r.add_position(at(t), seen, tracking(t));
    }
  }
  double heading = 0.0;
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
};

}  // namespace

TEST_CASE("gait regression: straights and turns give the step-length scale and the turn slowdown", "[fusion][gait]") {
  GaitRegression r;
  Walker w;
  w.walk(r, 0.0, 60.0, [](double) { return true; });
  // The particles' own means as the prior, far off: the fit does not lean on them.
  const auto s = r.solve(1.0, 0.0);
  REQUIRE(s);
  CHECK(s->windows >= 50);
  CHECK(s->scale == Approx(0.85).margin(0.02));
  CHECK(s->turn_slowdown_m_per_rad == Approx(0.2).margin(0.03));
  CHECK(r.rejected_windows() == 0);
}

TEST_CASE("gait regression: a stretch of turns only pins the speed in the turn, the prior the rest", "[fusion][gait]") {
  GaitRegression r;
  Walker w;
  // Only the turn phases are tracked (the lights are on in the corners only).
  w.walk(r, 0.0, 60.0, [](double t) { return std::fmod(t, 8.0) >= 6.0; });
  const auto s = r.solve(1.0, 0.0);
  REQUIRE(s);
  const double omega = std::numbers::pi / 4.0;
  // k s - A omega is what the turns observe: right within 2 %.
  CHECK(s->scale * 1.2 - s->turn_slowdown_m_per_rad * omega == Approx(0.85 * 1.2 - 0.2 * omega).epsilon(0.02));
}

TEST_CASE("gait regression: a jump of the track is not fitted, untracked stretches add nothing", "[fusion][gait]") {
  GaitRegression r;
  Walker w;
  // At 40 s the filter's position jumps 2 m (a re-initialisation onto another fix).
  w.walk(r, 0.0, 60.0, [](double) { return true; }, 3, Eigen::Vector2d(2.0, 0.0));
  const auto s = r.solve(1.0, 0.0);
  REQUIRE(s);
  CHECK(r.rejected_windows() == 1);
  CHECK(s->scale == Approx(0.85).margin(0.02));

  GaitRegression dark;
  Walker w2;
  w2.walk(dark, 0.0, 30.0, [](double) { return false; });
  CHECK(dark.windows() == 0);
  CHECK_FALSE(dark.solve(1.0, 0.0));  // nothing learnt: the particles keep their own

  GaitRegressionOptions off;
  off.enabled = false;
  GaitRegression disabled(off);
  Walker w3;
  w3.walk(disabled, 0.0, 30.0, [](double) { return true; });
  CHECK_FALSE(disabled.solve(1.0, 0.0));
}

TEST_CASE("gait regression: no answer from the first few windows of a walk", "[fusion][gait]") {
  GaitRegression r;
  Walker w;
  // 4.5 s tracked: four 1 s windows, fewer than min_windows (5).
  w.walk(r, 0.0, 4.5, [](double) { return true; });
  CHECK(r.windows() == 4);
  CHECK_FALSE(r.solve(1.0, 0.0));  // the particles keep their own k and A
  w.walk(r, 4.5, 6.5, [](double) { return true; });
  CHECK(r.windows() >= 5);
  CHECK(r.solve(1.0, 0.0));
}

TEST_CASE("gait regression: non-finite inputs are ignored", "[fusion][gait]") {
  GaitRegression r;
  Walker w;
  w.walk(r, 0.0, 30.0, [](double) { return true; });
  const auto before = r.solve(1.0, 0.0);
  REQUIRE(before);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.add_motion(nan, 0.0, Eigen::Vector2d(1.0, 0.0), 0.01);
  r.add_motion(1.0, nan, Eigen::Vector2d(1.0, 0.0), 0.01);
  r.add_motion(1.0, 0.0, Eigen::Vector2d(nan, 0.0), 0.01);
  r.add_position(at(31.0), Eigen::Vector2d(nan, 0.0), true);
  const auto after = r.solve(1.0, 0.0);
  REQUIRE(after);
  CHECK(after->scale == before->scale);
  CHECK_FALSE(r.solve(nan, 0.0));
}
