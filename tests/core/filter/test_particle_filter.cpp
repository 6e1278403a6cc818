#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <tbb/global_control.h>

#include "core/filter/fast_rng.hpp"
#include "core/filter/particle_filter.hpp"

using namespace luxloc;

namespace {

PositionMeasurement fix_at(double x, double y, double sigma) {
  PositionMeasurement m;
  m.z = {x, y};
  m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
  return m;
}

// Tracks a device moving at 1 m/s along x with noisy 30 Hz fixes; returns the final error.
double track(ParticleFilterOptions opt, int steps = 300) {
  ParticleFilter pf(opt);
  FastRng noise(3);
  double err = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double t = k / 30.0;
    MotionInput u;
    u.dt = 1.0 / 30.0;
    if (k > 0) pf.predict(u);
    pf.correct(fix_at(t + 0.05 * noise.normal(), 2.0 + 0.05 * noise.normal(), 0.05));
    const auto e = pf.estimate();
    REQUIRE(e.valid);
    err = std::hypot(e.p.x() - t, e.p.y() - 2.0);
  }
  return err;
}

}  // namespace

TEST_CASE("Particle filter tracks a moving device from noisy fixes", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 2000;
  REQUIRE(track(opt) < 0.06);
  opt.resample_every_correction = true;  // seed A's mode
  REQUIRE(track(opt) < 0.06);
}

TEST_CASE("Particle filter gives the same answer whatever the thread count", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 20000;  // several TBB chunks
  double one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    ParticleFilter pf(opt);
    pf.initialize({1, 1}, Eigen::Matrix2d::Identity());
    for (int k = 0; k < 20; ++k) {
      pf.predict(MotionInput{0.1, {0.1, 0.0}, true});
      pf.correct(fix_at(1 + 0.01 * k, 1, 0.1));
    }
    one = pf.estimate().p.x();
  }
  {
    ParticleFilter pf(opt);
    pf.initialize({1, 1}, Eigen::Matrix2d::Identity());
    for (int k = 0; k < 20; ++k) {
      pf.predict(MotionInput{0.1, {0.1, 0.0}, true});
      pf.correct(fix_at(1 + 0.01 * k, 1, 0.1));
    }
    many = pf.estimate().p.x();
  }
  REQUIRE(one == many);
}

TEST_CASE("Particle filter never emits NaN: bad input, underflow, kidnapping", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 1000;
  ParticleFilter pf(opt);
  pf.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);

  SECTION("non-finite measurement and motion are refused") {
    REQUIRE_FALSE(pf.correct(fix_at(NAN, 0, 0.1)).accepted);
    pf.predict(MotionInput{NAN, {0, 0}, true});
    pf.predict(MotionInput{0.01, {NAN, 1}, true});
    REQUIRE(pf.estimate().valid);
    REQUIRE(pf.estimate().p.allFinite());
  }
  SECTION("a fix 10 m away is gated, then the filter re-initialises on it") {
    int reinit = 0;
    for (int k = 0; k < 20; ++k) {
      const auto r = pf.correct(fix_at(10, 0, 0.05));
      reinit += r.reinitialized;
      REQUIRE(pf.estimate().p.allFinite());
    }
    REQUIRE(reinit == 1);
    REQUIRE(pf.estimate().p.x() == Approx(10).margin(0.05));
  }
  SECTION("a sigma so small that linear weights underflow is handled in log space") {
    PositionMeasurement m = fix_at(0.05, 0, 1e-9);  // exp(-d^2 / 2R) == 0 for every particle
    m.gate_sigma = 1e12;
    const auto r = pf.correct(m);
    REQUIRE(r.accepted);
    REQUIRE_FALSE(r.reinitialized);
    REQUIRE(pf.estimate().p.allFinite());
    REQUIRE(pf.estimate().p.x() == Approx(0.05).margin(0.03));  // the particle nearest the fix
  }
  SECTION("a likelihood that is zero (-inf) for every particle leaves the weights alone") {
    const double before = pf.estimate().p.x();
    REQUIRE_FALSE(pf.weigh([](double, double) { return -std::numeric_limits<double>::infinity(); }));
    REQUIRE_FALSE(pf.weigh([](double, double) { return std::nan(""); }));
    REQUIRE(pf.normalize_and_resample());
    REQUIRE(pf.estimate().p.x() == Approx(before).margin(1e-12));
  }
}
