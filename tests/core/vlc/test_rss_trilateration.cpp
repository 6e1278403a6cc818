// Received-signal-strength fix (core/vlc/rss_trilateration.cpp), SEEDS.md A S201 (corrected
// formula) and S203 (trilateration); and on rendered frames through the stripe decoder.
#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/sim/frame_renderer.hpp"
#include "core/vlc/rss_trilateration.hpp"
#include "core/vlc/stripe_decoder.hpp"

using namespace luxloc;

namespace {

const std::vector<Eigen::Vector3d> kLeds = {{0, 0, 3}, {2, 0, 3}, {0, 2, 3}, {2, 2, 3}, {1, 3.5, 3}};

// S201: P_r = C P_t h^2 / d^4.
std::vector<RssMeasurement> powers(const Eigen::Vector3d& receiver, double C, std::size_t n, double rel_noise = 0.0,
                                   std::mt19937_64* rng = nullptr) {
  std::normal_distribution<double> g(0.0, rel_noise);
  std::vector<RssMeasurement> out;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = kLeds[i] - receiver;
    const double pt = 1.0 + 0.1 * static_cast<double>(i);
    double pr = C * pt * v.z() * v.z() / std::pow(v.norm(), 4);
    if (rng) pr *= std::exp(g(*rng));
    out.push_back({kLeds[i], pt, pr});
  }
  return out;
}

}  // namespace

TEST_CASE("RSS distance: the corrected S201 formula inverts the channel", "[vlc]") {
  const double C = 3.7e5, pt = 1.3, h = 1.9;
  for (double r : {0.0, 0.5, 1.7}) {
    const double d = std::hypot(h, r);
    const double pr = C * pt * h * h / std::pow(d, 4);
    CHECK(rss_distance(C, pt, h, pr) == Approx(d).epsilon(1e-12));
    CHECK(rss_horizontal_distance(rss_distance(C, pt, h, pr), h) == Approx(r).margin(1e-6));
  }
  CHECK(std::isnan(rss_distance(C, pt, h, 0.0)));
  CHECK(std::isnan(rss_distance(-1.0, pt, h, 1.0)));
  CHECK(rss_horizontal_distance(1.0, 1.2) == 0.0);  // d < h from noise: directly below
}

TEST_CASE("RSS fix: exact powers give the exact position, C known or solved", "[vlc]") {
  const double C = 2.5e5;
  const Eigen::Vector3d rx(0.7, 1.3, 1.1);
  for (std::size_t n : {3u, 4u, 5u}) {
    RssOptions o;
    o.C = C;
    const VlcFix fix = rss_fix(powers(rx, C, n), rx.z(), o);
    INFO(n << " LEDs, C known");
    REQUIRE(fix.valid);
    CHECK(fix.method == VlcFix::Method::Rss);
    CHECK((fix.p_BinW - rx).norm() < 1e-6);
    CHECK(fix.residual_px < 1e-6);
  }
  for (std::size_t n : {4u, 5u}) {
    const VlcFix fix = rss_fix(powers(rx, C, n), rx.z(), RssOptions{});
    INFO(n << " LEDs, C solved");
    REQUIRE(fix.valid);
    CHECK((fix.p_BinW - rx).norm() < 1e-5);
  }
  CHECK_FALSE(rss_fix(powers(rx, C, 3), rx.z(), RssOptions{}).valid);  // C unknown needs 4
  // The lever arm moves the receiver's fix to the body origin.
  RssOptions o;
  o.C = C;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d lever(0.1, 0.0, 0.2);
  const VlcFix body = rss_fix(powers(rx, C, 4), rx.z(), o, R, lever);
  REQUIRE(body.valid);
  CHECK((body.p_BinW + R * lever - rx).norm() < 1e-6);
}

TEST_CASE("RSS fix: noisy powers give a bounded error that the covariance describes", "[vlc]") {
  const double C = 2.5e5, noise = 0.05;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> err;
  double nees = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d rx(0.3 + 1.4 * U(rng), 0.3 + 1.4 * U(rng), 1.0 + 0.4 * U(rng));
    RssOptions o;
    o.C = C;
    o.power_rel_sigma = noise;
    const VlcFix fix = rss_fix(powers(rx, C, 5, noise, &rng), rx.z(), o);
    REQUIRE(fix.valid);
    const Eigen::Vector2d d = (fix.p_BinW - rx).head<2>();
    err.push_back(d.norm());
    nees += d.dot(fix.cov_xy.inverse() * d);
  }
  std::sort(err.begin(), err.end());
  nees /= 300.0;
  INFO("5 % power noise: median " << err[150] << " m, p95 " << err[285] << " m, mean NEES " << nees);
  CHECK(err[150] < 0.06);
  CHECK(err[285] < 0.15);
  CHECK(nees > 1.2);
  CHECK(nees < 3.0);
}

TEST_CASE("RSS constant: least-squares calibration from known poses", "[vlc]") {
  const double C = 1.8e5;
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<RssSample> exact, noisy;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d rx(2 * U(rng), 2 * U(rng), 1.0 + 0.5 * U(rng));
    for (const RssMeasurement& m : powers(rx, C, 5)) exact.push_back({m, rx});
    for (const RssMeasurement& m : powers(rx, C, 5, 0.1, &rng)) noisy.push_back({m, rx});
  }
  const RssCalibration a = calibrate_rss_constant(exact);
  REQUIRE(a.valid);
  CHECK(a.C == Approx(C).epsilon(1e-9));
  CHECK(a.rms_log_residual < 1e-9);
  const RssCalibration b = calibrate_rss_constant(noisy);
  REQUIRE(b.valid);
  CHECK(b.samples == 1000);
  CHECK(b.C == Approx(C).epsilon(0.02));
  CHECK(b.rms_log_residual == Approx(0.1).epsilon(0.15));
  CHECK(b.rms_range_error_m < 0.1);
  CHECK_FALSE(calibrate_rss_constant({}).valid);
}

TEST_CASE("RSS fix: degenerate inputs are invalid and never NaN", "[vlc]") {
  const double C = 2.5e5;
  const Eigen::Vector3d rx(1, 1, 1);
  RssOptions o;
  o.C = C;
  auto never_nan = [](const VlcFix& f) {
    CHECK_FALSE(f.valid);
    CHECK(f.p_BinW.allFinite());
    CHECK(f.cov_xy.allFinite());
  };
  never_nan(rss_fix({}, rx.z(), o));
  never_nan(rss_fix(powers(rx, C, 2), rx.z(), o));
  never_nan(rss_fix(powers(rx, C, 4), std::numeric_limits<double>::quiet_NaN(), o));
  never_nan(rss_fix(powers(rx, C, 4), 3.5, o));  // receiver above the LEDs
  auto bad = powers(rx, C, 4);
  bad[0].received = -1.0;
  bad[1].received = std::numeric_limits<double>::quiet_NaN();
  never_nan(rss_fix(bad, rx.z(), o));  // two left
  std::vector<RssMeasurement> line;
  for (double x : {0.0, 1.0, 2.0, 3.0}) {
    const Eigen::Vector3d L(x, 0.5, 3.0), v = L - rx;
    line.push_back({L, 1.0, C * v.z() * v.z() / std::pow(v.norm(), 4)});
  }
  never_nan(rss_fix(line, rx.z(), o));  // collinear LEDs: mirror ambiguity
}

TEST_CASE("RSS on rendered frames: C calibrated on some frames, fixes on others", "[vlc]") {
  // A level camera looking up (the S201 geometry), unsaturated LEDs; the received power is
  // the decoder's blob energy over its stripe on-fraction.
  CameraModel cam;
  cam.fx = cam.fy = 300;  // wide: 4 to 6 LEDs in view
  cam.row_time_s = 20e-6;
  cam.exposure_s = 100e-6;
  cam.R_CtoB << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  std::vector<Led> leds;
  for (int i = 0; i < 9; ++i) {
    Led l;
    l.id = i + 1;
    l.freq_hz = 3000.0 * std::pow(1.1, i);  // >= 2 periods on a 30-row blob
    l.p_inW = Eigen::Vector3d(1.5 * (i % 3), 1.5 * (i / 3), 3.0);
    l.diameter_m = 0.2;
    leds.push_back(l);
  }
  const LedMap map(leds, "rss");
  const StripeDecoder decoder(cam, map);
  sim::RenderOptions ro;
  ro.peak_dn = 110;  // no clipping
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto frame_at = [&](const Eigen::Vector3d& p, double yaw) {
    const sim::PoseAt pose = [&](double) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T.translation() = p;
      return T;
    };
    std::vector<double> ph;
    for (int i = 0; i < 9; ++i) ph.push_back(U(rng));
    return decoder.decode(sim::render_frame(cam, map, pose, 0.0, ro, rng, ph).gray);
  };
  std::vector<RssSample> samples;
  for (int k = 0; k < 30; ++k) {
    const Eigen::Vector3d p(0.3 + 2.4 * U(rng), 0.3 + 2.4 * U(rng), 1.2);
    for (const RssMeasurement& m : rss_measurements_from(frame_at(p, 6.3 * U(rng)), map)) samples.push_back({m, p});
  }
  const RssCalibration cal = calibrate_rss_constant(samples);
  REQUIRE(cal.valid);
  std::vector<double> err;
  for (int k = 0; k < 60; ++k) {
    const Eigen::Vector3d p(0.3 + 2.4 * U(rng), 0.3 + 2.4 * U(rng), 1.2);
    RssOptions o;
    o.C = cal.C;
    const VlcFix fix = rss_fix(rss_measurements_from(frame_at(p, 6.3 * U(rng)), map), p.z(), o);
    if (fix.valid) err.push_back((fix.p_BinW - p).head<2>().norm());
  }
  std::sort(err.begin(), err.end());
  REQUIRE(err.size() >= 40);
  INFO("C = " << cal.C << " from " << cal.samples << " LED sightings, power RMS " << cal.rms_log_residual
              << " (log), range RMS " << cal.rms_range_error_m << " m; fix error median " << err[err.size() / 2]
              << " m, p90 " << err[err.size() * 9 / 10] << " m over " << err.size() << " frames");
  CHECK(cal.rms_log_residual < 0.05);
  CHECK(err[err.size() / 2] < 0.03);
  CHECK(err[err.size() * 9 / 10] < 0.06);
}
