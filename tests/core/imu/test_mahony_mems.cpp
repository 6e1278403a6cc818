// Issue 11: the attitude filter on the simulator's MEMS grades, on seeds it was not tuned on
// (tuning: 1-10; these: 201+), clean and with a steel pillar and a passing magnet.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/imu/mahony_filter.hpp"
#include "core/sim/imu_grade.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;

namespace {

struct YawErrors {
  double p50_deg = 0, p95_deg = 0, max_deg = 0;
  AhrsRejections rejections;
  Eigen::Vector3d bias_err = Eigen::Vector3d::Zero();  // at the end, rad/s
};

YawErrors yaw_errors(const std::string& scenario, const std::string& grade, const std::string& mag,
                     std::uint64_t seed, double duration_s, MahonyOptions o = {}) {
  sim::SimOptions so;
  so.seed = seed;
  so.duration_s = duration_s;
  so.imu = sim::imu_grade(grade);
  so.mag_disturbance = mag;
  const sim::Simulator sim(sim::make_scenario(scenario), so);
  MahonyFilter f(o);
  std::vector<double> err;
  for (const ImuSample& s : sim.imu_samples()) {
    f.update(s);
    err.push_back(std::abs(std::remainder(f.yaw() - sim.truth(ns_to_seconds(s.t)).yaw, 2 * std::numbers::pi)));
  }
  std::sort(err.begin(), err.end());
  constexpr double deg = 180.0 / std::numbers::pi;
  YawErrors y;
  y.p50_deg = err[err.size() / 2] * deg;
  y.p95_deg = err[err.size() * 95 / 100] * deg;
  y.max_deg = err.back() * deg;
  y.rejections = f.rejections();
  y.bias_err = f.gyro_bias() - sim.gyro_bias_track().back();
  return y;
}

}  // namespace

TEST_CASE("Mahony on a consumer-grade walk (hold-out seed): yaw p95 <= 2 deg clean, <= 5 deg with disturbances",
          "[imu]") {
  for (const char* mag : {"none", "both"}) {
    const YawErrors y = yaw_errors("walk", "consumer", mag, 201, 90.0);
    std::printf("[imu] consumer walk seed 201 (%s): yaw p50 %.2f p95 %.2f max %.2f deg, mag rejected %llu (%.1f s)\n",
                mag, y.p50_deg, y.p95_deg, y.max_deg, static_cast<unsigned long long>(y.rejections.mag_samples),
                y.rejections.mag_s);
    CHECK(y.p95_deg <= (std::string(mag) == "none" ? 2.0 : 5.0));
    CHECK(y.max_deg <= (std::string(mag) == "none" ? 3.0 : 7.0));
  }
}

TEST_CASE("Mahony rejects and counts a magnet passing a still device, and does not turn", "[imu]") {
  // Fails on the filter before issue 11 (magnitude gate 10 %, no heading gate): the magnet
  // turns the horizontal field by up to 49 deg while |m| changes by < 13 %.
  const YawErrors y = yaw_errors("static", "consumer", "magnet", 202, 30.0);
  std::printf("[imu] static + magnet seed 202: yaw max %.2f deg, mag rejected %llu (%.1f s, heading %llu)\n",
              y.max_deg, static_cast<unsigned long long>(y.rejections.mag_samples), y.rejections.mag_s,
              static_cast<unsigned long long>(y.rejections.mag_heading));
  CHECK(y.rejections.mag_samples > 100);
  CHECK(y.rejections.mag_heading > 50);
  CHECK(y.rejections.mag_adopted == 0);
  CHECK(y.max_deg <= 1.5);  // 11.5 deg before issue 11 (seed 202); the acc bias alone tilts ~0.5 deg of it
}

TEST_CASE("Mahony learns a 0.8 deg/s z bias through the magnetometer on a walk without standstill estimates", "[imu]") {
  // The at-rest estimate switched off: only the heading loop (ki_heading) can learn the bias.
  sim::SimOptions so;
  so.seed = 203;
  so.duration_s = 90.0;
  so.imu = sim::imu_grade("consumer");
  so.imu.gyro_bias_fixed = true;
  so.imu.gyro_bias_fixed_rps = Eigen::Vector3d(0, 0, 0.8 * std::numbers::pi / 180.0);
  so.imu.gyro_bias_rw_rps_sqrt_s = 0.0;
  const sim::Simulator sim(sim::make_scenario("walk"), so);
  MahonyOptions o;
  o.bias_at_rest = false;
  MahonyFilter f(o);
  for (const ImuSample& s : sim.imu_samples()) f.update(s);
  const double bz_deg = f.gyro_bias().z() * 180 / std::numbers::pi;
  std::printf("[imu] walk seed 203, 0.8 deg/s z bias, no at-rest estimate: learnt %.3f deg/s\n", bz_deg);
  CHECK(bz_deg == Approx(0.8).margin(0.15));
}

TEST_CASE("Mahony keeps the bias of the first standstill when the walk starts on a curve (poor grade)", "[imu]") {
  // Issue 11 regression (tuning seed 36, poor grade, clean field): the 2 s standstill learnt
  // the ~1 deg/s z bias, the walk's first curve ended the still run on the field's turn
  // verdict and the bias went back to 0: yaw p95 16.6 deg (5.3 without the field check).
  sim::SimOptions so;
  so.seed = 36;
  so.duration_s = 30.0;
  so.imu = sim::imu_grade("poor");
  const sim::Simulator sim(sim::make_scenario("walk"), so);
  const std::vector<Eigen::Vector3d> bias = sim.gyro_bias_track();
  const std::vector<ImuSample> samples = sim.imu_samples();
  MahonyFilter f;
  double worst_bias_err = 0.0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    f.update(samples[k]);
    const double t = ns_to_seconds(samples[k].t);
    if (t < 2.5 || t > 5.0) continue;  // the walk's first seconds
    const Eigen::Vector3d up = f.R_BtoW().row(2).transpose();
    worst_bias_err = std::max(worst_bias_err, std::abs(up.dot(f.gyro_bias() - bias[k])));
  }
  constexpr double deg = 180.0 / std::numbers::pi;
  const YawErrors y = yaw_errors("walk", "poor", "none", 36, 30.0);
  std::printf("[imu] poor walk seed 36: vertical bias error 2.5-5 s %.3f deg/s, yaw p95 %.2f max %.2f deg (30 s)\n",
              worst_bias_err * deg, y.p95_deg, y.max_deg);
  CHECK(worst_bias_err * deg < 0.3);  // 0.78 before the fix
  CHECK(y.p95_deg < 6.0);
}
