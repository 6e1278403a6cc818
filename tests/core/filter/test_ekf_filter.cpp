#include <catch2/catch.hpp>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/filter/ekf_filter.hpp"
#include "core/filter/fast_rng.hpp"

using namespace luxloc;

namespace {

PositionMeasurement fix_at(double x, double y, double sigma) {
  PositionMeasurement m;
  m.z = {x, y};
  m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
  return m;
}

bool symmetric_pd(const EkfFilter::Matrix4& P) {
  if ((P - P.transpose()).norm() > 1e-12 * (1.0 + P.norm())) return false;
  return Eigen::SelfAdjointEigenSolver<EkfFilter::Matrix4>(P).eigenvalues().minCoeff() > 0.0;
}

}  // namespace

TEST_CASE("EKF predict and position update match a hand computation", "[filter]") {
  EkfOptions o;
  o.velocity_tau_s = 0.0;  // seed C: pure constant velocity
  o.accel_noise_psd = 0.5;
  o.init_speed_sigma = 0.3;
  EkfFilter f(o);
  f.initialize({1.0, 2.0}, Eigen::Matrix2d::Identity() * 0.04);
  // Predict 0.1 s with a = (1, 0): per axis F = [[1, dt], [0, 1]], Q = q dt [[dt^2/4, dt/2], [dt/2, 1]].
  f.predict(MotionInput{0.1, {1.0, 0.0}, true});
  const double Ppp = 0.04 + 0.01 * 0.09 + 0.5 * 0.1 * 0.0025;  // 0.041025
  const double Ppv = 0.1 * 0.09 + 0.5 * 0.1 * 0.05;           // 0.0115
  const double Pvv = 0.09 + 0.05;                              // 0.14
  REQUIRE(f.state()(0) == Approx(1.0 + 0.5 * 0.01 * 1.0));    // p + a dt^2 / 2
  REQUIRE(f.state()(2) == Approx(0.1));                        // v + a dt
  REQUIRE(f.state()(1) == Approx(2.0));
  REQUIRE(f.covariance()(0, 0) == Approx(Ppp));
  REQUIRE(f.covariance()(0, 2) == Approx(Ppv));
  REQUIRE(f.covariance()(2, 2) == Approx(Pvv));
  REQUIRE(f.covariance()(0, 1) == Approx(0.0).margin(1e-15));
  // Position fix x = 1.5 (R = 0.01): S = Ppp + R, K = [Ppp, Ppv] / S.
  const double x0 = 1.005, v0 = 0.1;
  const CorrectionResult r = f.correct(fix_at(1.5, 2.0, 0.1));
  REQUIRE(r.accepted);
  const double S = Ppp + 0.01, Kp = Ppp / S, Kv = Ppv / S;
  REQUIRE(r.mahalanobis == Approx((1.5 - x0) / std::sqrt(S)));
  REQUIRE(f.state()(0) == Approx(x0 + Kp * (1.5 - x0)));
  REQUIRE(f.state()(2) == Approx(v0 + Kv * (1.5 - x0)));
  REQUIRE(f.state()(1) == Approx(2.0));
  REQUIRE(f.covariance()(0, 0) == Approx(Ppp * 0.01 / S));     // (1 - Kp) Ppp
  REQUIRE(f.covariance()(0, 2) == Approx(Ppv * 0.01 / S));     // (1 - Kp) Ppv
  REQUIRE(f.covariance()(2, 2) == Approx(Pvv - Ppv * Ppv / S));
  REQUIRE(symmetric_pd(f.covariance()));
  const PlanarEstimate e = f.estimate();
  REQUIRE(e.valid);
  REQUIRE(e.p.x() == Approx(f.state()(0)));
  REQUIRE(e.cov_p(0, 0) == Approx(f.covariance()(0, 0)));
}

TEST_CASE("EKF velocity decay and velocity update", "[filter]") {
  EkfOptions o;
  o.velocity_tau_s = 2.0;
  EkfFilter f(o);
  f.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  f.predict(MotionInput{0.5, {2.0, 0.0}, true});
  const double d = std::exp(-0.25);
  REQUIRE(f.state()(2) == Approx(d * 2.0 * 0.5));              // d (v + a dt)
  REQUIRE(f.state()(0) == Approx(0.5 * 0.5 * (0.0 + d * 1.0))); // dt (v + v') / 2
  // Zero-velocity update (5 cm/s): the velocity collapses, with a hand-computed gain.
  const double Pvv = f.covariance()(2, 2), v = f.state()(2);
  VelocityMeasurement zupt;
  zupt.R = Eigen::Matrix2d::Identity() * 0.0025;
  zupt.gate_sigma = 100;
  REQUIRE(f.correct_velocity(zupt).accepted);
  REQUIRE(f.state()(2) == Approx(v - Pvv / (Pvv + 0.0025) * v));
  REQUIRE(symmetric_pd(f.covariance()));
}

TEST_CASE("EKF gates outliers, re-initialises when lost, refuses NaN", "[filter]") {
  EkfFilter f;
  f.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  REQUIRE_FALSE(f.correct(fix_at(NAN, 0, 0.1)).accepted);
  f.predict(MotionInput{NAN, {0, 0}, true});
  f.predict(MotionInput{0.01, {NAN, 0}, true});
  REQUIRE(f.estimate().valid);
  REQUIRE(f.estimate().p.norm() < 1e-9);
  int reinit = 0, accepted = 0;
  for (int k = 0; k < 10; ++k) {
    const CorrectionResult r = f.correct(fix_at(10, 0, 0.05));
    reinit += r.reinitialized;
    accepted += r.accepted;
  }
  REQUIRE(reinit == 1);
  REQUIRE(accepted == 3);  // 8th rejection re-initialises, then two fixes agree
  REQUIRE(f.estimate().p.x() == Approx(10).margin(0.05));
  REQUIRE(f.reinit_count() == 1);
}

TEST_CASE("EKF covariance stays symmetric positive definite over a long run and an outage", "[filter]") {
  EkfFilter f;
  FastRng noise(4);
  f.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  for (int k = 0; k < 3000; ++k) {  // 30 s at 100 Hz, fixes at 30 Hz
    f.predict(MotionInput{0.01, {0.2 * noise.normal(), 0.2 * noise.normal()}, true});
    if (k % 3 == 0) f.correct(fix_at(0.05 * noise.normal(), 0.05 * noise.normal(), 0.05));
    REQUIRE(symmetric_pd(f.covariance()));
  }
  for (int k = 0; k < 6000; ++k) {  // 60 s without fixes
    f.predict(MotionInput{0.01, {0.3, -0.2}, true});
    REQUIRE(f.estimate().valid);
  }
  REQUIRE(symmetric_pd(f.covariance()));
  REQUIRE(f.state().tail<2>().norm() <= f.options().max_speed + 1e-9);
  REQUIRE(f.covariance()(0, 0) <= f.options().max_position_variance);
}
