// The simulator's IMU grades and magnetic disturbances (docs/SIMULATOR.md "IMU grades"):
// the default grade reproduces the historic IMU bit for bit, the consumer grade draws biases
// within 1 deg/s that walk, scale errors show in the readings, and the field bends only near
// the pillar and while the magnet passes.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/sim/imu_grade.hpp"
#include "core/sim/mag_disturbance.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;
using namespace luxloc::sim;

namespace {

Simulator make_sim(const std::string& scenario, const std::string& grade, std::uint64_t seed,
                   const std::string& mag = "none", double duration_s = 20.0) {
  SimOptions o;
  o.seed = seed;
  o.duration_s = duration_s;
  o.imu = imu_grade(grade);
  o.mag_disturbance = mag;
  return Simulator(make_scenario(scenario), o);
}

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

TEST_CASE("IMU grade default is the historic simulator IMU, sample for sample", "[sim]") {
  SimOptions historic;
  historic.seed = 3;
  historic.duration_s = 10.0;
  const std::vector<ImuSample> a = Simulator(make_scenario("walk"), historic).imu_samples();
  const std::vector<ImuSample> b = make_sim("walk", "default", 3, "none", 10.0).imu_samples();
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    REQUIRE(a[k].acc_inB == b[k].acc_inB);
    REQUIRE(a[k].gyro_inB == b[k].gyro_inB);
    REQUIRE(a[k].mag_inB == b[k].mag_inB);
  }
}

TEST_CASE("IMU grade consumer: gyro biases within 1 deg/s that walk, scale errors, unknown names throw", "[sim]") {
  double largest = 0.0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const Simulator s = make_sim("static", "consumer", seed, "none", 30.0);
    largest = std::max(largest, s.imu_biases().gyro.cwiseAbs().maxCoeff());
    CHECK(s.imu_biases().gyro.cwiseAbs().maxCoeff() <= 1.0 * kDeg + 1e-12);
    CHECK(s.imu_biases().gyro_scale != Eigen::Vector3d::Ones());
    const std::vector<Eigen::Vector3d> track = s.gyro_bias_track();
    CHECK(track.front() == s.imu_biases().gyro);
    CHECK((track.back() - track.front()).norm() > 0.0);
    // 0.005 deg/s/sqrt(s) over 30 s: 0.027 deg/s per axis (1 sigma); 6 sigma in norm is far.
    CHECK((track.back() - track.front()).norm() < 0.2 * kDeg);
  }
  CHECK(largest > 0.7 * kDeg);  // the draws do reach the top of the range
  // The static device reads its drifting bias, the ideal grade reads nothing.
  const Simulator ideal = make_sim("static", "ideal", 1);
  for (const ImuSample& m : ideal.imu_samples()) REQUIRE(m.gyro_inB.norm() < 1e-12);
  CHECK_THROWS_AS(imu_grade("militaryish"), std::invalid_argument);
  CHECK_THROWS_AS(make_sim("static", "default", 1, "lava"), std::invalid_argument);
}

TEST_CASE("IMU grade scale errors multiply the true rate", "[sim]") {
  SimOptions o;
  o.duration_s = 20.0;
  o.imu = ImuNoise::none();
  o.imu.gyro_scale_sigma = 0.02;
  const Simulator s(make_scenario("walk"), o);
  const std::vector<ImuSample> m = s.imu_samples();
  const Eigen::Vector3d scale = s.imu_biases().gyro_scale;
  for (std::size_t k = 0; k < m.size(); k += 97) {
    const Eigen::Vector3d w = s.truth(s.imu_time_s(k)).omega_inB;
    CHECK((m[k].gyro_inB - scale.cwiseProduct(w)).norm() < 1e-12);
  }
}

TEST_CASE("Magnetic disturbances: the field bends near the pillar and while the magnet passes, nowhere else",
          "[sim]") {
  const Simulator s = make_sim("walk", "ideal", 1, "both", 90.0);
  const MagneticField& f = s.magnetic_field();
  REQUIRE(f.steel.size() == 1);
  REQUIRE(f.magnets.size() == 1);
  const Eigen::Vector3d earth = f.earth_inW;
  // Beside the pillar at 27 s, the magnet at 54 s: a field far from the Earth's.
  const BodyState near = s.truth(27.0);
  CHECK((f.at(near.p_BinW, near.t) - earth).norm() > 5.0);
  CHECK((f.at(Eigen::Vector3d(0, 0, 1), 54.0) - earth).norm() > 20.0);
  // Far from both (the start, 2 s in): the Earth's field within 0.1 uT.
  const BodyState start = s.truth(2.0);
  CHECK((f.at(start.p_BinW, start.t) - earth).norm() < 0.1);
  // The magnetometer reads the disturbed field.
  const std::vector<ImuSample> m = s.imu_samples();
  const std::size_t k = 5400;  // 54 s
  const BodyState at = s.truth(s.imu_time_s(k));
  CHECK((m[k].mag_inB - at.R_BtoW.transpose() * f.at(at.p_BinW, at.t)).norm() < 1e-9);
}
