// Single-frame camera fixes (core/vlc/camera_geometry_fix.cpp) and the measurement function.
#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

#include "core/vlc/camera_geometry_fix.hpp"

using namespace luxloc;

namespace {

CameraModel camera_up() {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = 460;
  c.fy = 462;
  c.cx = 318;
  c.cy = 243;
  c.dist = {-0.12, 0.03, 0.001, -0.0005, 0.0};
  // Looking up, camera x along body -y (SPEC R_body_camera columns), with a lever arm.
  c.R_CtoB << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  c.p_CinB = Eigen::Vector3d(0.08, -0.03, 0.12);
  return c;
}

Eigen::Matrix3d attitude(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

const std::vector<Eigen::Vector3d> kLeds = {{1.0, 1.0, 3.0}, {2.6, 1.2, 3.0}, {1.2, 2.4, 3.0}, {2.4, 2.6, 3.05}, {1.9, 0.3, 2.95}};

std::vector<LedSighting> sight(const CameraModel& cam, const Eigen::Matrix3d& R, const Eigen::Vector3d& p, std::size_t n,
                               double noise_px = 0.0, std::mt19937_64* rng = nullptr) {
  std::normal_distribution<double> g(0.0, noise_px);
  std::vector<LedSighting> out;
  for (std::size_t i = 0; i < n; ++i) {
    const auto uv = predict_pixel(cam, R, p, kLeds[i]);
    REQUIRE(uv);
    Eigen::Vector2d z = *uv;
    if (rng) z += Eigen::Vector2d(g(*rng), g(*rng));
    out.push_back({kLeds[i], z});
  }
  return out;
}

}  // namespace

TEST_CASE("measurement function: predicted pixel round-trips through the bearing", "[vlc]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.7, 0.05, -0.08);
  const Eigen::Vector3d p(1.7, 1.6, 1.1);
  const auto uv = predict_pixel(cam, R, p, kLeds[0]);
  REQUIRE(uv);
  // The bearing of the predicted pixel points at the LED.
  const Eigen::Vector3d ray = R * cam.R_CtoB * cam.bearing(*uv);
  const Eigen::Vector3d to_led = (kLeds[0] - (p + R * cam.p_CinB)).normalized();
  CHECK(ray.dot(to_led) == Approx(1.0).epsilon(1e-12));
  // An LED below the camera is not seen.
  CHECK_FALSE(predict_pixel(cam, R, p, Eigen::Vector3d(1.7, 1.6, 0.2)).has_value());
}

TEST_CASE("bearing fix: exact rays give the exact position with 1, 2, 3 and 5 LEDs", "[vlc]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(2.1, -0.06, 0.09);
  const Eigen::Vector3d p(1.75, 1.65, 1.05);
  for (std::size_t n : {1u, 2u, 3u, 5u}) {
    const VlcFix fix = bearing_fix(sight(cam, R, p, n), cam, R, p.z());
    INFO(n << " LEDs");
    REQUIRE(fix.valid);
    CHECK(fix.method == VlcFix::Method::Bearing);
    CHECK(fix.n_leds == static_cast<int>(n));
    CHECK((fix.p_BinW - p).norm() < 1e-6);
    CHECK(fix.residual_px < 1e-6);
    CHECK(fix.cov_xy.allFinite());
    CHECK(fix.cov_xy.determinant() > 0.0);
  }
  // Height unknown: solved from >= 2 LEDs; 1 LED is not enough.
  for (std::size_t n : {2u, 3u, 5u}) {
    const VlcFix fix = bearing_fix(sight(cam, R, p, n), cam, R);
    REQUIRE(fix.valid);
    CHECK((fix.p_BinW - p).norm() < 1e-6);
    CHECK(fix.sigma_z > 0.0);
  }
  CHECK_FALSE(bearing_fix(sight(cam, R, p, 1), cam, R).valid);
  // Height given but asked to solve it from well-spread LEDs.
  CameraFixOptions o;
  o.solve_height = true;
  const VlcFix zfix = bearing_fix(sight(cam, R, p, 5), cam, R, 0.5 /* wrong */, o);
  REQUIRE(zfix.valid);
  CHECK((zfix.p_BinW - p).norm() < 1e-6);
}

TEST_CASE("bearing fix: covariance matches the scatter under pixel and attitude noise", "[vlc]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.3, 0.04, 0.02);
  const Eigen::Vector3d p(1.8, 1.7, 1.0);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  CameraFixOptions o;
  o.pixel_sigma = 1.0;
  o.attitude_sigma_rad = 0.01;
  o.height_sigma_m = 0.0;
  for (std::size_t n : {1u, 4u}) {
    double nees = 0.0;
    Eigen::Matrix2d cov_used = Eigen::Matrix2d::Zero();
    const int trials = 400;
    for (int k = 0; k < trials; ++k) {
      // Attitude error: the IMU's R differs from the true one by a small rotation.
      const Eigen::Vector3d e(g(rng) * o.attitude_sigma_rad, g(rng) * o.attitude_sigma_rad, g(rng) * o.attitude_sigma_rad);
      const Eigen::Matrix3d R_meas = Eigen::AngleAxisd(e.norm(), e.normalized()).toRotationMatrix() * R;
      const VlcFix fix = bearing_fix(sight(cam, R, p, n, o.pixel_sigma, &rng), cam, R_meas, p.z(), o);
      REQUIRE(fix.valid);
      const Eigen::Vector2d d = (fix.p_BinW - p).head<2>();
      nees += d.dot(fix.cov_xy.inverse() * d);
      cov_used = fix.cov_xy;
    }
    nees /= trials;
    INFO(n << " LEDs: mean NEES " << nees << " (2 expected), sigma_x " << std::sqrt(cov_used(0, 0)) << " m");
    CHECK(nees > 1.4);
    CHECK(nees < 2.8);
  }
}

TEST_CASE("PnP fix: pose from 3 and more LEDs without the attitude", "[vlc]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(-1.2, 0.1, -0.07);
  const Eigen::Vector3d p(1.8, 1.5, 1.2);
  for (std::size_t n : {4u, 5u}) {
    const VlcFix fix = pnp_fix(sight(cam, R, p, n), cam);
    INFO(n << " LEDs");
    REQUIRE(fix.valid);
    CHECK(fix.method == VlcFix::Method::Pnp);
    CHECK((fix.p_BinW - p).norm() < 1e-5);
    CHECK((fix.R_BtoW - R).norm() < 1e-5);
    CHECK(fix.residual_px < 1e-3);
  }
  const VlcFix three = pnp_fix(sight(cam, R, p, 3), cam);  // minimal: one of P3P's solutions
  REQUIRE(three.valid);
  CHECK(three.residual_px < 1e-3);
  // With noise the error stays within a few sigma of the covariance.
  std::mt19937_64 rng(12);
  const VlcFix noisy = pnp_fix(sight(cam, R, p, 5, 0.5, &rng), cam, CameraFixOptions{.pixel_sigma = 0.5});
  REQUIRE(noisy.valid);
  const Eigen::Vector2d d = (noisy.p_BinW - p).head<2>();
  CHECK(d.dot(noisy.cov_xy.inverse() * d) < 16.0);
}

TEST_CASE("camera fixes: degenerate inputs are invalid and never NaN", "[vlc]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.4, 0.0, 0.0);
  const Eigen::Vector3d p(1.7, 1.7, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto never_nan = [](const VlcFix& f) {
    CHECK_FALSE(f.valid);
    CHECK(f.p_BinW.allFinite());
    CHECK(f.cov_xy.allFinite());
    CHECK(std::isfinite(f.residual_px));
  };
  never_nan(bearing_fix(std::vector<LedSighting>{}, cam, R, 1.0));
  never_nan(pnp_fix(std::vector<LedSighting>{}, cam));
  Eigen::Matrix3d R_nan = R;
  R_nan(0, 0) = nan;
  never_nan(bearing_fix(sight(cam, R, p, 3), cam, R_nan, 1.0));
  never_nan(bearing_fix(sight(cam, R, p, 3), cam, 2.0 * R, 1.0));  // not a rotation
  auto bad_uv = sight(cam, R, p, 2);
  bad_uv[1].uv.x() = nan;
  never_nan(bearing_fix(bad_uv, cam, R, 1.0));
  // LEDs below the camera (device height above the ceiling).
  never_nan(bearing_fix(sight(cam, R, p, 2), cam, R, 3.5));
  // Collinear LEDs: PnP cannot fix a pose.
  std::vector<LedSighting> line;
  for (double x : {0.5, 1.5, 2.5, 3.5}) {
    const Eigen::Vector3d L(x, 2.0, 3.0);
    line.push_back({L, *predict_pixel(cam, R, p, L)});
  }
  never_nan(pnp_fix(line, cam));
  // Only two LEDs for PnP.
  never_nan(pnp_fix(sight(cam, R, p, 2), cam));
  // Rejected and border observations are not used.
  LedObservation rejected;
  rejected.reject_reason = "no map match";
  CHECK(sightings_from({rejected}, LedMap()).empty());
}
