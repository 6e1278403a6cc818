#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/filter/fast_rng.hpp"
#include "core/filter/filter_factory.hpp"

using namespace luxloc;

namespace {

PositionMeasurement fix(const Eigen::Vector2d& p, double sigma, FastRng& noise) {
  PositionMeasurement m;
  const double nx = noise.normal(), ny = noise.normal();
  m.z = Eigen::Vector2d(p.x() + sigma * nx, p.y() + sigma * ny);
  m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
  return m;
}

}  // namespace

TEST_CASE("Filter factory knows pf, gpf and ekf", "[filter]") {
  REQUIRE(filter_names() == std::vector<std::string>{"pf", "gpf", "ekf"});
  for (const auto& name : filter_names()) REQUIRE(make_planar_filter(FilterSettings{name}) != nullptr);
  REQUIRE(dynamic_cast<ParticleFilter*>(make_planar_filter(FilterSettings{"gpf"}).get())->options().policy ==
          ResamplingPolicy::Genetic);
  REQUIRE(dynamic_cast<EkfFilter*>(make_planar_filter(FilterSettings{"ekf"}).get()) != nullptr);
  REQUIRE_THROWS_AS(make_planar_filter(FilterSettings{"ukf"}), std::invalid_argument);
}

TEST_CASE("Every filter is back within 0.3 m of truth within 5 s of fixes after a kidnapping", "[filter]") {
  // A device walking a 2 m circle at 1 m/s with 30 Hz fixes (5 cm), 100 Hz IMU
  // (centripetal acceleration), kidnapped 10 m away; then a 60 s fix outage.
  const std::string name = GENERATE(as<std::string>{}, "pf", "gpf", "ekf");
  FilterSettings s{name};
  s.pf.particles = 2000;
  auto f = make_planar_filter(s);
  FastRng noise(11);
  const double omega = 0.5, radius = 2.0;
  double offset_x = 0.0;
  const auto truth = [&](double t) {
    return Eigen::Vector2d(offset_x + radius * std::cos(omega * t), radius * std::sin(omega * t));
  };
  const auto acc = [&](double t) {
    const double c = -omega * omega * radius;
    return Eigen::Vector2d(c * std::cos(omega * t), c * std::sin(omega * t));
  };
  const auto run = [&](double t0, double t1, bool fixes, double acc_bias = 0.0) {
    // Returns the time (s after t0) from which the error stays below 0.3 m (-1: never).
    double since = -1.0;
    int k = 0;
    for (double t = t0; t < t1; t += 0.01, ++k) {
      f->predict(MotionInput{0.01, acc(t) + Eigen::Vector2d(acc_bias, 0.0), true});
      if (fixes && k % 3 == 0) f->correct(fix(truth(t), 0.05, noise));
      const PlanarEstimate e = f->estimate();
      REQUIRE(e.valid);
      REQUIRE(e.p.allFinite());
      REQUIRE(e.cov_p.allFinite());
      const double err = (e.p - truth(t)).norm();
      if (err < 0.3 && since < 0) since = t - t0;
      if (err >= 0.3) since = -1.0;
    }
    return since;
  };
  f->initialize(truth(0), Eigen::Matrix2d::Identity() * 0.01);
  REQUIRE(run(0.0, 10.0, true) == Approx(0.0).margin(0.05));  // tracks from the start
  offset_x = 10.0;                                             // kidnapped
  const double back = run(10.0, 15.0, true);
  INFO(name << ": back within 0.3 m after " << back << " s");
  REQUIRE(back >= 0.0);
  REQUIRE(back <= 5.0);
  // 60 s of prediction only, the accelerometer biased by 0.2 m/s^2: no NaN (checked
  // inside), and the dead reckoning drifts off.
  REQUIRE(run(15.0, 75.0, false, 0.2) == -1.0);
  const double back2 = run(75.0, 80.0, true);
  INFO(name << ": after the outage, back within 0.3 m after " << back2 << " s");
  REQUIRE(back2 >= 0.0);
  REQUIRE(back2 <= 5.0);
}

TEST_CASE("Every filter survives a correction whose likelihood underflows", "[filter]") {
  const std::string name = GENERATE(as<std::string>{}, "pf", "gpf", "ekf");
  auto f = make_planar_filter(FilterSettings{name});
  f->initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  PositionMeasurement m;
  m.z = {0.5, 0.0};
  m.R = Eigen::Matrix2d::Identity() * 1e-30;  // exp(-0.25 / 2e-30) underflows everywhere
  m.gate_sigma = std::numeric_limits<double>::infinity();
  f->correct(m);
  REQUIRE(f->estimate().valid);
  REQUIRE(f->estimate().p.allFinite());
  REQUIRE(f->estimate().p.x() == Approx(0.5).margin(0.35));
}
