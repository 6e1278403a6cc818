// Issue 12: what the particle filter's gait calibration must carry into an outage.
// - A walker who slows down in turns more than the gait model assumes: the per-particle
//   turn slowdown (GaitNoise::turn_slowdown_*) learns it from the fixes, so one step-length
//   scale fits straights and turns alike and the dead reckoning through an outage keeps pace.
// - widen_gait: the spread of k and d grows to the floors of an outage (the reported sigma
//   then grows with the gait model's real error), the means stay.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/filter/fast_rng.hpp"
#include "core/filter/particle_filter.hpp"

using namespace luxloc;

namespace {

// Stadium walk: 5 s straight, 3 s of a half turn (omega = pi/3 rad/s), repeated. The PDR
// reports 1.2 / 0.9 m/s everywhere (scale 0.9) and pays out the turned angle; the walker
// walks 1.2 m/s straight and loses 0.35 m per radian turned (1.2 - 0.35 |omega| in turns):
// 2 prior sigma beyond the population's mean slowdown (GaitNoise::turn_slowdown0, 0.225).
// Fixes (3 cm, 10 Hz) for `fixes_s`, then none for `outage_s`.
struct Outcome {
  double max_err_outage_m = 0.0;
};

constexpr double kSpeed = 1.2, kScale = 0.9, kTurnSlowdown = 0.35;

double turn_rate(double t) { return std::fmod(t, 8.0) < 5.0 ? 0.0 : std::numbers::pi / 3.0; }

Outcome stadium(ParticleFilter& f, double fixes_s, double outage_s) {
  const double dt = 0.01;
  Eigen::Vector2d p(0.0, 0.0);
  double heading = 0.0;
  f.initialize(p, Eigen::Matrix2d::Identity() * 0.01);
  FastRng noise(7);
  Outcome o;
  const int n = static_cast<int>((fixes_s + outage_s) / dt);
  for (int k = 1; k <= n; ++k) {
    const double t = k * dt, w = turn_rate(t);
    heading += w * dt;
    p += (kSpeed - kTurnSlowdown * w) * dt * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    MotionInput u;
    u.dt = dt;
    u.has_gait = true;
    u.gait.speed_mps = kSpeed / kScale;
    u.gait.heading_rad = heading;
    u.gait.length_sigma_m = 0.05 * 0.67;
    u.gait.heading_sigma_rad = 0.035;
    u.gait.step_period_s = 0.55;
    u.gait.turn_rate_rps = w;
    u.gait.turn_paid_rps = w;
    f.predict(u);
    if (t <= fixes_s && k % 10 == 0) {
      PositionMeasurement m;
      m.z = p + 0.03 * Eigen::Vector2d(noise.normal(), noise.normal());
      m.R = Eigen::Matrix2d::Identity() * 0.03 * 0.03;
      f.correct(m);
    }
    const PlanarEstimate e = f.estimate();
    REQUIRE(e.valid);
    if (t > fixes_s) o.max_err_outage_m = std::max(o.max_err_outage_m, (e.p - p).norm());
  }
  return o;
}

ParticleFilterOptions options() {
  ParticleFilterOptions opt;
  opt.particles = 4000;
  opt.heading.enabled = false;  // the heading is exact here
  return opt;
}

}  // namespace

TEST_CASE("Particle filter, pedestrian model: the walker's own turn slowdown is learnt and kept through an outage",
          "[filter][motion]") {
  ParticleFilter pf(options());
  // 40 s of fixes (five straights, five turns), then 16 s in the dark: two straights, two turns.
  const Outcome o = stadium(pf, 40.0, 16.0);
  const ParticleFilter::GaitEstimate g = pf.gait_estimate();
  REQUIRE(g.valid);
  INFO("scale " << g.scale << ", turn slowdown " << g.turn_slowdown_m_per_rad << "; outage max " << o.max_err_outage_m);
  CHECK(g.scale == Approx(kScale).margin(0.03));
  CHECK(g.turn_slowdown_m_per_rad == Approx(kTurnSlowdown).margin(0.07));
  CHECK(o.max_err_outage_m < 0.35);

  // Without the turn-slowdown state (the population's mean slowdown for every walker) one
  // scale must fit straights and turns: the outage drifts further.
  ParticleFilterOptions fixed = options();
  fixed.gait.turn_slowdown_sigma0 = fixed.gait.turn_slowdown_walk = 0.0;
  ParticleFilter pf_fixed(fixed);
  const Outcome uncal = stadium(pf_fixed, 40.0, 16.0);
  INFO("without the state: outage max " << uncal.max_err_outage_m);
  CHECK(uncal.max_err_outage_m > 1.5 * o.max_err_outage_m);
}

TEST_CASE("Particle filter, pedestrian model: widen_gait spreads k and d to the floors, keeps the means",
          "[filter][motion]") {
  ParticleFilter pf(options());
  stadium(pf, 20.0, 0.0);
  const ParticleFilter::GaitEstimate before = pf.gait_estimate();
  REQUIRE(before.valid);
  REQUIRE(before.scale_sigma < 0.03);  // the fixes pinned k down
  pf.widen_gait(0.05, 0.026);
  const ParticleFilter::GaitEstimate after = pf.gait_estimate();
  CHECK(after.scale == Approx(before.scale).margin(2e-3));
  CHECK(after.heading_offset_rad == Approx(before.heading_offset_rad).margin(2e-3));
  CHECK(after.scale_sigma == Approx(0.05).margin(0.003));
  CHECK(after.heading_offset_sigma == Approx(0.026).margin(0.002));
  // Floors below the spread change nothing.
  pf.widen_gait(0.01, 0.001);
  const ParticleFilter::GaitEstimate again = pf.gait_estimate();
  CHECK(again.scale_sigma == Approx(after.scale_sigma).epsilon(1e-4));
  CHECK(again.heading_offset_sigma == Approx(after.heading_offset_sigma).epsilon(1e-4));
}
