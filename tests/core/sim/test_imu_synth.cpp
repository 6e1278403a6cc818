// IMU synthesis: readings at rest, noise and bias statistics, and strapdown integration of
// the noise-free readings reproducing the true trajectory (derivative consistency).
#include <catch2/catch.hpp>
#include <cmath>

#include "core/sim/imu_synth.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;
using namespace luxloc::sim;

namespace {

struct Nav {
  Eigen::Quaterniond q;
  Eigen::Vector3d v, p;
};

// One strapdown derivative: q' = q (0, w/2), v' = R f - g, p' = v.
struct NavRate {
  Eigen::Vector4d dq;
  Eigen::Vector3d dv, dp;
};
NavRate rate(const Nav& n, const ImuSample& m) {
  const Eigen::Quaterniond w(0.0, 0.5 * m.gyro_inB.x(), 0.5 * m.gyro_inB.y(), 0.5 * m.gyro_inB.z());
  NavRate r;
  r.dq = (n.q * w).coeffs();
  r.dv = n.q.toRotationMatrix() * m.acc_inB - Eigen::Vector3d(0, 0, kGravity);
  r.dp = n.v;
  return r;
}
Nav step(const Nav& n, const NavRate& r, double h) {
  Nav o;
  o.q.coeffs() = n.q.coeffs() + h * r.dq;
  o.v = n.v + h * r.dv;
  o.p = n.p + h * r.dp;
  return o;
}

}  // namespace

TEST_CASE("IMU at rest: gravity up, no rotation, the Earth field rotated into the body", "[sim]") {
  const Scenario sc = make_scenario("static");
  const BodyState s = sc.trajectory->state(3.0);
  const ImuSample m = ideal_imu(s);
  CHECK((m.acc_inB - Eigen::Vector3d(0, 0, kGravity)).norm() < 1e-12);
  CHECK(m.gyro_inB.norm() < 1e-12);
  // Facing yaw = 0.5 rad: the field's horizontal part appears rotated by -0.5 rad.
  const Eigen::Vector3d m_W = ImuNoise{}.mag_field_inW;
  CHECK((m.mag_inB - Eigen::AngleAxisd(-0.5, Eigen::Vector3d::UnitZ()) * m_W).norm() < 1e-9);
  CHECK(std::atan2(m.mag_inB.x(), m.mag_inB.y()) == Approx(0.5).margin(1e-9));  // field points north

  // Measured: mean = truth + bias, spread = the white noise.
  SimOptions o;
  o.seed = 21;
  const Simulator sim(sc, o);
  const std::vector<ImuSample> imu = sim.imu_samples();
  REQUIRE(imu.size() == 3000);
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_g = Eigen::Vector3d::Zero();
  for (const ImuSample& x : imu) {
    mean_a += x.acc_inB / imu.size();
    mean_g += x.gyro_inB / imu.size();
  }
  double var_a = 0;
  for (const ImuSample& x : imu) var_a += (x.acc_inB - mean_a).squaredNorm() / (3.0 * imu.size());
  const double tol_a = 4.0 * o.imu.acc_noise_mps2 / std::sqrt(3000.0), tol_g = 4.0 * o.imu.gyro_noise_rps / std::sqrt(3000.0);
  CHECK((mean_a - Eigen::Vector3d(0, 0, kGravity) - sim.imu_biases().acc).cwiseAbs().maxCoeff() < tol_a);
  CHECK((mean_g - sim.imu_biases().gyro).cwiseAbs().maxCoeff() < tol_g);
  CHECK(std::sqrt(var_a) == Approx(o.imu.acc_noise_mps2).epsilon(0.05));
  CHECK(sim.imu_biases().acc.norm() > 0.0);
  CHECK(sim.imu_biases().acc.cwiseAbs().maxCoeff() < 4.0 * o.imu.acc_bias_sigma_mps2);
  CHECK(sim.imu_biases().gyro.cwiseAbs().maxCoeff() < 4.0 * o.imu.gyro_bias_sigma_rps);
}

TEST_CASE("Integrating the noise-free IMU reproduces the walk (RK4 at 1 kHz)", "[sim]") {
  const Scenario sc = make_scenario("walk");
  const Trajectory& tr = *sc.trajectory;
  // 5 s of walking through two corners (t = 5..10 s covers x 3.6 -> 7, turn north at (7, 1)).
  const double t0 = 5.0, t1 = 10.0, h = 1e-3;
  const BodyState s0 = tr.state(t0);
  Nav n{Eigen::Quaterniond(s0.R_BtoW), s0.v_BinW, s0.p_BinW};
  for (double t = t0; t < t1 - 1e-9; t += h) {
    const ImuSample m0 = ideal_imu(tr.state(t)), mh = ideal_imu(tr.state(t + 0.5 * h)), m1 = ideal_imu(tr.state(t + h));
    const NavRate k1 = rate(n, m0), k2 = rate(step(n, k1, 0.5 * h), mh), k3 = rate(step(n, k2, 0.5 * h), mh),
                  k4 = rate(step(n, k3, h), m1);
    n.q.coeffs() += h / 6.0 * (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq);
    n.q.normalize();
    n.v += h / 6.0 * (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv);
    n.p += h / 6.0 * (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp);
  }
  const BodyState s1 = tr.state(t1);
  CHECK((s1.p_BinW - s0.p_BinW).norm() > 3.5);  // it did walk
  CHECK((n.p - s1.p_BinW).norm() < 1e-4);
  CHECK((n.v - s1.v_BinW).norm() < 1e-4);
  CHECK(Eigen::AngleAxisd(n.q.toRotationMatrix().transpose() * s1.R_BtoW).angle() < 1e-6);
}

TEST_CASE("The 100 Hz noise-free IMU file data dead-reckons 5 s within a few cm", "[sim]") {
  SimOptions o;
  o.imu = ImuNoise::none();
  o.duration_s = 12.0;
  const Simulator sim(make_scenario("walk"), o);
  const std::vector<ImuSample> imu = sim.imu_samples();
  const std::size_t k0 = 500, k1 = 1000;  // t = 5 .. 10 s
  const BodyState s0 = sim.truth(sim.imu_time_s(k0));
  Eigen::Matrix3d R = s0.R_BtoW;
  Eigen::Vector3d v = s0.v_BinW, p = s0.p_BinW;
  const Eigen::Vector3d g(0, 0, kGravity);
  for (std::size_t k = k0; k < k1; ++k) {
    const double dt = sim.imu_time_s(k + 1) - sim.imu_time_s(k);
    const Eigen::Vector3d w = 0.5 * (imu[k].gyro_inB + imu[k + 1].gyro_inB);
    const Eigen::Matrix3d R1 = R * Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix();
    const Eigen::Vector3d a0 = R * imu[k].acc_inB - g, a1 = R1 * imu[k + 1].acc_inB - g;
    p += v * dt + (a0 / 3.0 + a1 / 6.0) * dt * dt;
    v += 0.5 * (a0 + a1) * dt;
    R = R1;
  }
  const BodyState s1 = sim.truth(sim.imu_time_s(k1));
  CHECK((p - s1.p_BinW).norm() < 0.03);
  CHECK(Eigen::AngleAxisd(R.transpose() * s1.R_BtoW).angle() < 2e-3);
}
