#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
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

// A fixed scenario: 20 predict/correct steps with acceleration input.
void run_steps(ParticleFilter& pf) {
  pf.initialize({100.0, 200.0}, Eigen::Matrix2d::Identity());
  for (int k = 0; k < 20; ++k) {
    pf.predict(MotionInput{0.1, {0.1, 0.0}, true});
    pf.correct(fix_at(100.0 + 0.01 * k, 200.0, 0.1));
  }
}

}  // namespace

TEST_CASE("Particle filter tracks a moving device from noisy fixes", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 2000;
  REQUIRE(track(opt) < 0.06);
  opt.resample_every_correction = true;  // seed A's mode
  REQUIRE(track(opt) < 0.06);
  for (auto scheme : {ResamplingScheme::Stratified, ResamplingScheme::Multinomial, ResamplingScheme::Residual}) {
    INFO(to_string(scheme));
    opt.scheme = scheme;
    REQUIRE(track(opt) < 0.06);
  }
}

TEST_CASE("Particle filter gives bit-identical particles whatever the thread count", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 20000;  // several 4096-particle chunks
  SECTION("SIR, systematic") {}
  SECTION("SIR, systematic, every correction (ancestors and gather in one pass)") {
    opt.resample_every_correction = true;
  }
  SECTION("SIR, stratified, every correction") {
    opt.scheme = ResamplingScheme::Stratified;
    opt.resample_every_correction = true;
  }
  SECTION("genetic") {
    opt.policy = ResamplingPolicy::Genetic;
    opt.resample_every_correction = true;
  }
  SECTION("KLD-sampling and injection") {
    opt.kld.enabled = true;
    opt.kld.min_particles = 5000;
    opt.kld.max_particles = 30000;
    opt.resample_every_correction = true;
    opt.injection.enabled = true;
    opt.injection.region = Eigen::AlignedBox2d(Eigen::Vector2d(90, 190), Eigen::Vector2d(110, 210));
  }
  ParticleFilter one(opt), many(opt);
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    run_steps(one);
  }
  run_steps(many);
  REQUIRE(one.size() == many.size());
  REQUIRE(one.resample_count() > 0);
  const ParticleSet& a = one.particles();
  const ParticleSet& b = many.particles();
  REQUIRE(a.x == b.x);
  REQUIRE(a.y == b.y);
  REQUIRE(a.vx == b.vx);
  REQUIRE(a.vy == b.vy);
  REQUIRE(one.estimate().p == many.estimate().p);
  REQUIRE(one.estimate().cov_p == many.estimate().cov_p);
}

TEST_CASE("Particle filter estimate is the weighted mean and covariance of its particles", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 10000;
  opt.resample_threshold = 0.0;  // keep the weights
  ParticleFilter pf(opt);
  pf.initialize({5.0, -3.0}, (Eigen::Matrix2d() << 0.04, 0.01, 0.01, 0.09).finished());
  pf.predict(MotionInput{0.05, {0.3, -0.2}, true});
  REQUIRE(pf.correct(fix_at(5.1, -3.05, 0.15)).accepted);
  REQUIRE(pf.resample_count() == 0);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero(), vel = Eigen::Vector2d::Zero();
  double wsum = 0.0;
  for (std::size_t i = 0; i < pf.size(); ++i) {
    wsum += pf.weight(i);
    mean += pf.weight(i) * pf.position(i);
    vel += pf.weight(i) * pf.velocity(i);
  }
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < pf.size(); ++i) {
    const Eigen::Vector2d d = pf.position(i) - mean;
    cov += pf.weight(i) * d * d.transpose();
  }
  const PlanarEstimate e = pf.estimate();
  REQUIRE(wsum == Approx(1.0).epsilon(1e-5));
  REQUIRE((e.p - mean).norm() < 1e-5);
  REQUIRE((e.v - vel).norm() < 1e-5);
  REQUIRE((e.cov_p - cov).norm() < 1e-6);
  // The fix pulled the mean towards it, and shrank the spread.
  REQUIRE(e.p.x() > 5.02);
  REQUIRE(e.cov_p(0, 0) < 0.04);
  // n_eff = 1 / sum w^2.
  double s2 = 0.0;
  for (std::size_t i = 0; i < pf.size(); ++i) s2 += pf.weight(i) * pf.weight(i);
  REQUIRE(pf.n_eff() == Approx(1.0 / s2).epsilon(1e-4));
}

TEST_CASE("Particle filter never emits NaN: bad input, underflow, kidnapping", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 1000;
  ParticleFilter pf(opt);
  pf.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);

  SECTION("non-finite measurement and motion are refused") {
    REQUIRE_FALSE(pf.correct(fix_at(NAN, 0, 0.1)).accepted);
    PositionMeasurement singular = fix_at(0, 0, 0.1);
    singular.R.setZero();
    REQUIRE_FALSE(pf.correct(singular).accepted);
    pf.predict(MotionInput{NAN, {0, 0}, true});
    pf.predict(MotionInput{0.01, {NAN, 1}, true});
    pf.predict(MotionInput{std::numeric_limits<double>::infinity(), {0, 0}, false});
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
    REQUIRE(pf.reinit_count() == 1);
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
  SECTION("a likelihood that is zero (-inf) or NaN for every particle leaves the weights alone") {
    const double before = pf.estimate().p.x();
    REQUIRE_FALSE(pf.weigh([](double, double) { return -std::numeric_limits<double>::infinity(); }));
    REQUIRE_FALSE(pf.weigh([](double, double) { return std::nan(""); }));
    REQUIRE_FALSE(pf.weigh([](double, double) { return std::numeric_limits<double>::infinity(); }));
    REQUIRE(pf.normalize_and_resample());
    REQUIRE(pf.estimate().p.x() == Approx(before).margin(1e-12));
  }
  SECTION("NaN for some particles only: they get zero weight and are never copied") {
    REQUIRE(pf.weigh([](double x, double) { return x > 0.0 ? std::nan("") : -x * x; }));
    for (std::size_t i = 0; i < pf.size(); ++i)
      if (pf.position(i).x() > 0.0) REQUIRE(pf.weight(i) == 0.0);
    REQUIRE(pf.n_eff() < 600);  // about half the particles died
    pf.normalize_and_resample();
    REQUIRE(pf.resample_count() == 1);
    // After resampling (3 mm roughening) no particle is far on the dead side.
    for (std::size_t i = 0; i < pf.size(); ++i) REQUIRE(pf.position(i).x() < 0.02);
  }
}

TEST_CASE("Particle filter survives a 60 s fix outage on prediction alone", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 2000;
  ParticleFilter pf(opt);
  FastRng noise(9);
  double t = 0.0;
  for (; t < 5.0; t += 1.0 / 30) {  // converge, walking along x at 1 m/s
    pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
    pf.correct(fix_at(t + 0.05 * noise.normal(), 0.05 * noise.normal(), 0.05));
  }
  const double t_out = t;
  for (; t < t_out + 60.0; t += 0.01) {  // 100 Hz IMU, biased acceleration, no fix
    pf.predict(MotionInput{0.01, {0.3, -0.2}, true});
    const PlanarEstimate e = pf.estimate();
    REQUIRE(e.valid);
    REQUIRE(e.p.allFinite());
    REQUIRE(e.cov_p.allFinite());
    REQUIRE(e.v.norm() <= opt.max_speed + 1e-4);
  }
  REQUIRE(std::sqrt(pf.estimate().cov_p.trace()) > 1.0);  // it knows it is lost
  // Fixes again (the device stood still at x = 7 since the outage): back within 0.3 m.
  double back_after = -1.0;
  for (double s = 0.0; s < 5.0; s += 1.0 / 30) {
    pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
    pf.correct(fix_at(7.0 + 0.05 * noise.normal(), 0.05 * noise.normal(), 0.05));
    const double err = (pf.estimate().p - Eigen::Vector2d(7.0, 0.0)).norm();
    if (err < 0.3 && back_after < 0) back_after = s;
    if (err >= 0.3) back_after = -1.0;
  }
  INFO("back within 0.3 m after " << back_after << " s");
  REQUIRE(back_after >= 0.0);
  REQUIRE(back_after < 1.0);
}

TEST_CASE("Random-particle injection recovers a kidnapped filter that gating cannot", "[filter]") {
  // Gating off (huge gate, no re-initialisation): only the injection can bring the filter
  // to the new place, and it does so from the likelihood averages alone.
  const auto run = [](bool inject) {
    ParticleFilterOptions opt;
    opt.particles = 3000;
    opt.max_consecutive_rejections = 1 << 30;
    // Slow walker: selection of the fastest particles cannot drag the set 10 m in 5 s.
    opt.max_speed = 1.0;
    opt.injection.enabled = inject;
    opt.injection.region = Eigen::AlignedBox2d(Eigen::Vector2d(-2, -4), Eigen::Vector2d(12, 4));
    ParticleFilter pf(opt);
    FastRng noise(21);
    const auto fix = [&](double x) {
      PositionMeasurement m = fix_at(x + 0.05 * noise.normal(), 0.05 * noise.normal(), 0.05);
      m.gate_sigma = 1e9;
      return m;
    };
    for (int k = 0; k < 300; ++k) {  // 10 s at the origin
      pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
      pf.correct(fix(0.0));
    }
    REQUIRE(pf.estimate().p.norm() < 0.05);
    REQUIRE(pf.injected_count() == 0);  // nothing injected while the fixes match
    for (int k = 0; k < 150; ++k) {  // kidnapped to (10, 0): 5 s of fixes
      pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
      pf.correct(fix(10.0));
      REQUIRE(pf.estimate().p.allFinite());
      if ((pf.estimate().p - Eigen::Vector2d(10, 0)).norm() < 0.3) return (k + 1) / 30.0;
    }
    return 1e9;
  };
  const double with = run(true);
  const double without = run(false);
  INFO("recovered after " << with << " s with injection, " << without << " s without");
  REQUIRE(with <= 2.0);
  REQUIRE(without > 5.0);
}

TEST_CASE("Particle filter velocity update pulls the velocity towards the measurement", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 4000;
  ParticleFilter pf(opt);
  pf.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  for (int k = 0; k < 20; ++k) pf.predict(MotionInput{0.05, {1.0, 0.0}, true});
  REQUIRE(pf.estimate().v.x() > 0.5);
  VelocityMeasurement zupt;  // a still detector: zero velocity, 5 cm/s
  zupt.R = Eigen::Matrix2d::Identity() * 0.0025;
  zupt.gate_sigma = 100.0;
  REQUIRE(pf.correct_velocity(zupt).accepted);
  REQUIRE(std::abs(pf.estimate().v.x()) < 0.15);
  zupt.v = {NAN, 0};
  REQUIRE_FALSE(pf.correct_velocity(zupt).accepted);
}

TEST_CASE("Particle filter's chunked systematic resampling copies each particle within one of n w_i", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 20000;  // five chunks, parallel
  opt.roughening_m = 0.0;  // children sit exactly on their parent
  opt.resample_every_correction = true;
  ParticleFilter pf(opt);
  pf.initialize({3, 4}, Eigen::Matrix2d::Identity());
  // A peaked likelihood with a dead region: many particles get no child, a few get many.
  REQUIRE(pf.weigh([](double x, double y) {
    return x > 3.8 ? -std::numeric_limits<double>::infinity() : -((x - 3.5) * (x - 3.5) + (y - 4) * (y - 4)) / 0.02;
  }));
  std::map<std::pair<float, float>, double> expected;
  const double n = static_cast<double>(pf.size());
  for (std::size_t i = 0; i < pf.size(); ++i)
    expected[{pf.particles().x[i], pf.particles().y[i]}] += n * pf.weight(i);
  REQUIRE(pf.normalize_and_resample());
  REQUIRE(pf.resample_count() == 1);
  REQUIRE(pf.size() == opt.particles);
  std::map<std::pair<float, float>, double> copies;
  for (std::size_t i = 0; i < pf.size(); ++i) copies[{pf.particles().x[i], pf.particles().y[i]}] += 1.0;
  double worst = 0.0;
  for (const auto& [p, nw] : expected) {
    const auto it = copies.find(p);
    worst = std::max(worst, std::abs((it == copies.end() ? 0.0 : it->second) - nw));
  }
  for (const auto& [p, c] : copies) REQUIRE(expected.count(p) == 1);  // only existing particles
  INFO("worst |copies - n w| = " << worst);
  REQUIRE(worst < 1.0 + 1e-3);
  for (std::size_t i = 0; i < pf.size(); ++i) REQUIRE(pf.position(i).x() <= 3.8);  // dead never copied
}

TEST_CASE("Particle filter's systematic resampling spreads one chunk's many children over threads, identically", "[filter]") {
  // Every weight in the first 4096-particle chunk (the others dead): that chunk's
  // particles get all 40000 children, which its pieces copy in parallel; the particles
  // and the estimate must not depend on the thread count, and no dead particle is copied.
  ParticleFilterOptions opt;
  opt.particles = 40000;
  opt.resample_every_correction = true;
  ParticleFilter one(opt), many(opt);
  const auto peaked = [&](ParticleFilter& pf) {
    pf.initialize({0, 0}, Eigen::Matrix2d::Identity());
    // Mark the particles of the first chunk by their x: a likelihood that is alive only
    // for those x values.
    std::set<float> alive(pf.particles().x.begin(), pf.particles().x.begin() + 4096);
    REQUIRE(pf.weigh([&](double x, double) {
      return alive.count(static_cast<float>(x)) ? -x * x : -std::numeric_limits<double>::infinity();
    }));
    REQUIRE(pf.normalize_and_resample());
    REQUIRE(pf.resample_count() == 1);
    // Each child sits within the (bounded, triangular) roughening of a live parent.
    const float reach = 2.5f * static_cast<float>(opt.roughening_m);
    std::size_t orphans = 0;
    for (std::size_t i = 0; i < pf.size(); ++i) {
      const float x = pf.particles().x[i];
      const auto it = alive.lower_bound(x - reach);
      if (it == alive.end() || *it > x + reach) ++orphans;
    }
    REQUIRE(orphans == 0);
  };
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    peaked(one);
  }
  peaked(many);
  REQUIRE(one.size() == opt.particles);
  REQUIRE(one.particles().x == many.particles().x);
  REQUIRE(one.particles().y == many.particles().y);
  REQUIRE(one.particles().vx == many.particles().vx);
  REQUIRE(one.estimate().p == many.estimate().p);
  REQUIRE(one.estimate().cov_p == many.estimate().cov_p);
}

TEST_CASE("A refused update between a weighing and the resampling changes nothing", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 20000;
  opt.roughening_m = 0.0;
  opt.resample_every_correction = true;
  ParticleFilter a(opt), b(opt);
  const auto lik = [](double x, double) { return -(x - 0.2) * (x - 0.2) / 0.01; };
  for (ParticleFilter* pf : {&a, &b}) {
    pf->initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.04);
    REQUIRE(pf->weigh(lik));
  }
  // b also sees an update whose likelihood is zero everywhere: refused, no trace.
  REQUIRE_FALSE(b.weigh([](double, double) { return -std::numeric_limits<double>::infinity(); }));
  REQUIRE(a.normalize_and_resample());
  REQUIRE(b.normalize_and_resample());
  REQUIRE(a.particles().x == b.particles().x);
  REQUIRE(a.estimate().p == b.estimate().p);
  // Posterior mean: prior N(0, 0.04), likelihood N(0.2, 0.005): 0.2 * 0.04 / 0.045 = 0.178.
  REQUIRE(a.estimate().p.x() == Approx(0.178).margin(0.01));
}

TEST_CASE("Global set (initialize_uniform): the fused resampling keeps its size until one hypothesis, then shrinks, identically on any thread count", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 2000;
  opt.resample_every_correction = true;
  const Eigen::AlignedBox2d floor(Eigen::Vector2d(0, 0), Eigen::Vector2d(60, 30));
  const auto run = [&](ParticleFilter& pf, std::vector<std::size_t>& sizes) {
    pf.initialize_uniform(floor, 30000);
    REQUIRE(pf.localising());
    // Two hypotheses 20 m apart, then only the first: the set keeps 30000 while both live.
    const auto two = [](double x, double y) {
      const double a = (x - 10) * (x - 10) + (y - 10) * (y - 10), b = (x - 30) * (x - 30) + (y - 10) * (y - 10);
      return -std::min(a, b) / (2 * 0.3 * 0.3);
    };
    const auto one = [](double x, double y) { return -((x - 10) * (x - 10) + (y - 10) * (y - 10)) / (2 * 0.3 * 0.3); };
    for (int k = 0; k < 6; ++k) {
      pf.predict(MotionInput{0.05, {0.0, 0.0}, true});
      REQUIRE(pf.weigh(k < 3 ? std::function<double(double, double)>(two) : std::function<double(double, double)>(one)));
      REQUIRE(pf.normalize_and_resample());
      sizes.push_back(pf.size());
    }
  };
  ParticleFilter a(opt), b(opt);
  std::vector<std::size_t> sa, sb;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    run(a, sa);
  }
  run(b, sb);
  REQUIRE(sa == sb);
  CHECK(sa.front() == 30000);  // two hypotheses: still global
  CHECK(sa.back() == 2000);    // one left: the normal count
  CHECK_FALSE(a.localising());
  REQUIRE(a.particles().x == b.particles().x);
  REQUIRE(a.particles().y == b.particles().y);
  CHECK((a.estimate().p - Eigen::Vector2d(10, 10)).norm() < 0.1);
}
