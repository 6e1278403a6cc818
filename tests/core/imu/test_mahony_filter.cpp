#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "core/common/csv_reader.hpp"
#include "core/filter/fast_rng.hpp"
#include "core/imu/mahony_filter.hpp"
#include "sim_walk.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

// IMU reading of a static device with attitude R_BtoW in the ENU field (0, 22, -42) uT.
ImuSample static_sample(const Eigen::Matrix3d& R_BtoW, TimeNs t, const Eigen::Vector3d& gyro_bias) {
  ImuSample s;
  s.t = t;
  s.acc_inB = R_BtoW.transpose() * Eigen::Vector3d(0, 0, 9.80665);
  s.gyro_inB = gyro_bias;
  s.mag_inB = R_BtoW.transpose() * Eigen::Vector3d(0, 22, -42);
  s.has_mag = true;
  return s;
}

Eigen::Matrix3d ypr(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

TEST_CASE("Mahony aligns roll, pitch and yaw at rest (SEEDS C.1)", "[imu]") {
  const double yaw = 2.0, pitch = -0.2, roll = 0.3;
  MahonyFilter f;
  f.update(static_sample(ypr(yaw, pitch, roll), 0, Eigen::Vector3d::Zero()));
  REQUIRE(f.initialized());
  CHECK(f.yaw() == Approx(yaw).margin(1e-9));
  CHECK(f.pitch() == Approx(pitch).margin(1e-9));
  CHECK(f.roll() == Approx(roll).margin(1e-9));
}

TEST_CASE("Mahony learns a gyro bias and holds the attitude (SEEDS C.3)", "[imu]") {
  const Eigen::Vector3d bias(0.01, -0.008, 0.012);  // ~0.6 deg/s
  const Eigen::Matrix3d R = ypr(0.5, 0.05, -0.1);
  MahonyOptions opt;
  opt.ki = 0.05;
  MahonyFilter f(opt);
  FastRng rng(1);
  for (int k = 0; k < 100 * 120; ++k) {
    ImuSample s = static_sample(R, TimeNs{k} * 10'000'000, bias);
    s.gyro_inB += 0.003 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    s.acc_inB += 0.02 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    f.update(s);
  }
  CHECK((f.gyro_bias() - bias).norm() < 0.002);
  CHECK(f.yaw() == Approx(0.5).margin(0.01));
  CHECK(f.roll() == Approx(-0.1).margin(0.005));
  CHECK(f.pitch() == Approx(0.05).margin(0.005));
}

TEST_CASE("Mahony follows a rotation and ignores non-finite samples", "[imu]") {
  MahonyFilter f;
  const double rate = 0.5;  // rad/s about world z
  for (int k = 0; k <= 200; ++k) {
    const double t = k * 0.01;
    ImuSample s = static_sample(ypr(rate * t, 0, 0), TimeNs{k} * 10'000'000, Eigen::Vector3d::Zero());
    s.gyro_inB = Eigen::Vector3d(0, 0, rate);
    f.update(s);
    if (k == 100) {
      ImuSample bad = s;
      bad.t += 1;
      bad.gyro_inB.x() = NAN;
      f.update(bad);
    }
  }
  CHECK(f.rejected_samples() == 1);
  CHECK(f.yaw() == Approx(1.0).margin(0.01));
}

// ---- figures on the simulator's walk and on real data ----------------------------------

namespace {

struct AttitudeErrors {
  double roll_rms_deg = 0, pitch_rms_deg = 0, yaw_end_deg = 0;
};

// Runs the filter over the simulated walk; without a magnetometer the heading is compared
// relative to the start (it has no absolute reference).
AttitudeErrors run_on_walk(const test::SimWalk& w, bool use_mag) {
  MahonyOptions o;
  o.use_magnetometer = use_mag;
  MahonyFilter f(o);
  double sr = 0, sp = 0, yaw0e = 0, yaw0t = 0;
  std::size_t n = 0;
  for (const ImuSample& s : w.imu) {
    f.update(s);
    const sim::BodyState tr = w.simulator.truth(ns_to_seconds(s.t));
    if (n == 0) yaw0e = f.yaw(), yaw0t = tr.yaw;
    const double er = std::remainder(f.roll() - tr.roll, 2 * std::numbers::pi);
    const double ep = std::remainder(f.pitch() - tr.pitch, 2 * std::numbers::pi);
    sr += er * er;
    sp += ep * ep;
    ++n;
  }
  const sim::BodyState end = w.simulator.truth(ns_to_seconds(w.imu.back().t));
  const double ey = use_mag ? f.yaw() - end.yaw : (f.yaw() - yaw0e) - (end.yaw - yaw0t);
  constexpr double deg = 180.0 / std::numbers::pi;
  return {std::sqrt(sr / n) * deg, std::sqrt(sp / n) * deg, std::remainder(ey, 2 * std::numbers::pi) * deg};
}

}  // namespace

TEST_CASE("Mahony on the simulated 90 s walk: roll/pitch rms <= 1 deg, yaw at the end <= 2 deg (mag) / 5 deg (none)",
          "[imu]") {
  for (std::uint64_t seed : {1u, 2u}) {
    const test::SimWalk& w = test::sim_walk(seed);
    const AttitudeErrors with = run_on_walk(w, true), without = run_on_walk(w, false);
    std::printf("[imu] walk seed %llu: mag: roll rms %.3f pitch rms %.3f yaw end %.3f deg; no mag: yaw end %.3f deg\n",
                static_cast<unsigned long long>(seed), with.roll_rms_deg, with.pitch_rms_deg, with.yaw_end_deg,
                without.yaw_end_deg);
    CHECK(with.roll_rms_deg <= 1.0);
    CHECK(with.pitch_rms_deg <= 1.0);
    CHECK(std::abs(with.yaw_end_deg) <= 2.0);
    CHECK(without.roll_rms_deg <= 1.0);
    CHECK(without.pitch_rms_deg <= 1.0);
    CHECK(std::abs(without.yaw_end_deg) <= 5.0);
  }
}

TEST_CASE("Mahony without the bias-at-rest estimate drifts in yaw without a magnetometer", "[imu]") {
  // The control for the test above: it is the at-rest bias that holds the heading.
  const test::SimWalk& w = test::sim_walk(1);
  MahonyOptions o;
  o.use_magnetometer = false;
  o.bias_at_rest = false;
  o.ki = 0.0;
  MahonyFilter f(o);
  for (const ImuSample& s : w.imu) f.update(s);
  const sim::BodyState end = w.simulator.truth(ns_to_seconds(w.imu.back().t));
  const double drift_deg = std::abs(std::remainder(f.yaw() - end.yaw, 2 * std::numbers::pi)) * 180 / std::numbers::pi;
  CHECK(drift_deg > 5.0);  // the sim's z gyro bias integrates over 90 s
}

TEST_CASE("Mahony ignores a magnetic disturbance and holds the heading of a still device however long", "[imu]") {
  // Fails on the filter before issue 11: it adopted the field after the timeout, still or not.
  MahonyOptions opt;
  opt.mag_rejection_timeout_s = 5.0;
  MahonyFilter f(opt);
  const Eigen::Matrix3d R = ypr(0.3, 0.0, 0.0);
  TimeNs t = 0;
  auto feed = [&](double seconds, const Eigen::Vector3d& field_inW) {
    for (int k = 0; k < seconds * 100; ++k, t += 10'000'000) {
      ImuSample s = static_sample(R, t, Eigen::Vector3d::Zero());
      s.mag_inB = R.transpose() * field_inW;
      f.update(s);
    }
  };
  feed(3.0, {0, 22, -42});
  REQUIRE(f.yaw() == Approx(0.3).margin(1e-3));
  // A steel cabinet: weaker field pointing elsewhere, for 3 s (< timeout): heading holds.
  feed(3.0, {15, 10, -30});
  CHECK(f.mag_rejected_samples() > 250);
  CHECK(f.yaw() == Approx(0.3).margin(1e-3));
  // Lasting, but the gyro says still: a still device did not walk into another field.
  feed(30.0, {15, 10, -30});
  CHECK(f.yaw() == Approx(0.3).margin(1e-3));
  CHECK(f.rejections().mag_adopted == 0);
  CHECK(f.rejections().mag_s == Approx(33.0).margin(0.1));
}

TEST_CASE("Mahony adopts a lasting new field once the device moves in it", "[imu]") {
  MahonyOptions opt;
  opt.mag_rejection_timeout_s = 5.0;
  MahonyFilter f(opt);
  TimeNs t = 0;
  double yaw = 0.3;
  const Eigen::Vector3d field_new(15, 10, -30);
  for (int k = 0; k < 300; ++k, t += 10'000'000) f.update(static_sample(ypr(yaw, 0, 0), t, Eigen::Vector3d::Zero()));
  REQUIRE(f.yaw() == Approx(0.3).margin(1e-3));
  // Turning back and forth (0.3 rad at 0.5 rad/s) in the new field for 40 s.
  for (int k = 0; k < 4000; ++k, t += 10'000'000) {
    const double tt = k * 0.01, rate = 0.15 * std::cos(0.5 * tt);
    yaw = 0.3 + 0.3 * std::sin(0.5 * tt);
    ImuSample s = static_sample(ypr(yaw, 0, 0), t, Eigen::Vector3d::Zero());
    s.gyro_inB = {0, 0, rate};
    s.mag_inB = ypr(yaw, 0, 0).transpose() * field_new;
    f.update(s);
  }
  CHECK(f.rejections().mag_adopted >= 1);
  const double yaw_new = yaw + std::atan2(15.0, 10.0);  // north now reads as this heading
  CHECK(std::abs(std::remainder(f.yaw() - yaw_new, 2 * std::numbers::pi)) < 0.05);
  CHECK(f.gyro_bias().norm() < 0.002);  // the heading offset was not taken for a bias
}

TEST_CASE("Mahony learns a 0.8 deg/s gyro bias from a 1 s standstill", "[imu]") {
  const Eigen::Vector3d bias = Eigen::Vector3d(0.5, -0.3, 0.8) * std::numbers::pi / 180.0;
  MahonyFilter f;
  FastRng rng(7);
  const Eigen::Matrix3d R = ypr(1.0, 0.02, -0.03);
  for (int k = 0; k < 100; ++k) {  // 1.0 s at 100 Hz
    ImuSample s = static_sample(R, TimeNs{k} * 10'000'000, bias);
    s.gyro_inB += 0.005 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    s.acc_inB += 0.02 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    f.update(s);
  }
  CHECK(f.still());
  // 60 samples of mean after the 0.4 s window: 0.005 / sqrt(60) rad/s = 0.04 deg/s (1 sigma).
  CHECK((f.gyro_bias() - bias).norm() * 180 / std::numbers::pi < 0.15);
}

TEST_CASE("Mahony agrees with the Fusion AHRS reference on the real fusion_ahrs log", "[imu]") {
  const auto dir = test::shared_dir() / "realdata" / "fusion_ahrs";
  if (!std::filesystem::exists(dir / "imu.csv")) {
    WARN("real data missing: " << dir.string());
    return;
  }
  CsvReader imu((dir / "imu.csv").string()), ref((dir / "reference_attitude.csv").string());
  const int c[10] = {imu.require_column("t"),  imu.require_column("ax"), imu.require_column("ay"),
                     imu.require_column("az"), imu.require_column("gx"), imu.require_column("gy"),
                     imu.require_column("gz"), imu.require_column("mx"), imu.require_column("my"),
                     imu.require_column("mz")};
  const int rr = ref.require_column("roll_deg"), rp = ref.require_column("pitch_deg"),
            ry = ref.require_column("yaw_nwu_deg"), rt = ref.require_column("t");
  MahonyFilter f;
  double sr = 0, sp = 0, sy = 0, max_r = 0, max_p = 0, max_y = 0;
  std::size_t n = 0, n_yaw = 0;
  std::vector<std::pair<double, double>> late_yaw;  // (t, yaw deg) after 100 s: the still part
  auto wrap_deg = [](double a) { return std::remainder(a, 360.0); };
  while (imu.next_row() && ref.next_row()) {
    const double t = imu.number(c[0]);
    REQUIRE(ref.number(rt) == Approx(t).margin(1e-6));
    ImuSample s;
    s.t = seconds_to_ns(t);
    s.acc_inB = {imu.number(c[1]), imu.number(c[2]), imu.number(c[3])};
    s.gyro_inB = {imu.number(c[4]), imu.number(c[5]), imu.number(c[6])};
    s.mag_inB = {imu.number(c[7]), imu.number(c[8]), imu.number(c[9])};
    s.has_mag = true;
    f.update(s);
    if (t < 5.0) continue;  // both filters converge from their own start
    constexpr double deg = 180.0 / std::numbers::pi;
    const double er = wrap_deg(f.roll() * deg - ref.number(rr)), ep = wrap_deg(f.pitch() * deg - ref.number(rp));
    sr += er * er, sp += ep * ep, ++n;
    max_r = std::max(max_r, std::abs(er)), max_p = std::max(max_p, std::abs(ep));
    // README: yaw_enu = yaw_nwu + 90. From ~102 s the field magnitude drops from ~44 to ~38 uT
    // while the sensor lies still; Fusion adopts the disturbed field after its 5 s rejection
    // timeout (its yaw swings by 150 deg with no rotation), so its yaw is no reference there.
    if (t < 100.0) {
      const double ey = wrap_deg(f.yaw() * deg - (ref.number(ry) + 90.0));
      sy += ey * ey, ++n_yaw;
      max_y = std::max(max_y, std::abs(ey));
    } else {
      late_yaw.emplace_back(t, f.yaw() * deg);
    }
  }
  // Issue 11: the last 30 s (a still sensor while the field fades 44 -> 38 uT) must not turn
  // the heading by more than the field allows; measured 1.00 deg now (1.18 before the still-run
  // fixes of 2026-12-04, 0.5 with the attitude of
  // 2026-12-02, 70 deg before the magnetometer gates): the bound leaves room for gyro noise.
  REQUIRE(!late_yaw.empty());
  REQUIRE(late_yaw.back().first - late_yaw.front().first > 30.0);
  const double t_from = late_yaw.back().first - 30.0;
  const auto from = std::find_if(late_yaw.begin(), late_yaw.end(), [t_from](const auto& s) { return s.first >= t_from; });
  double turn = 0.0;
  for (auto it = from; it != late_yaw.end(); ++it) turn = std::max(turn, std::abs(wrap_deg(it->second - from->second)));
  std::printf("[imu] fusion_ahrs: heading turn over the last 30 s (still, field fading) %.2f deg\n", turn);
  CHECK(turn < 2.0);
  REQUIRE(n > 10000);
  const double rms_r = std::sqrt(sr / n), rms_p = std::sqrt(sp / n), rms_y = std::sqrt(sy / n_yaw);
  std::printf("[imu] fusion_ahrs vs reference: roll rms %.2f max %.2f, pitch rms %.2f max %.2f, yaw (t<100 s) rms %.2f "
              "max %.2f deg\n",
              rms_r, max_r, rms_p, max_p, rms_y, max_y);
  CHECK(rms_r < 1.0);
  CHECK(rms_p < 1.0);
  CHECK(max_r < 3.0);
  CHECK(max_p < 3.0);
  CHECK(rms_y <= 2.0);  // issue 11: yaw rms <= 2 deg over the moving part (measured 0.99; 1.17 before the still-run fixes of 2026-12-04, 0.90 before the field-turn check)
  CHECK(max_y < 6.0);
}
