// The device height from the camera geometry (core/vlc/camera_height.cpp, issue 16 part 3):
// two LEDs' angle, one LED's apparent size.
#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/vlc/camera_height.hpp"
#include "core/vlc/vlc_fix.hpp"

using namespace luxloc;

namespace {

CameraModel camera_up() {
  CameraModel c;
  c.fx = 460;
  c.fy = 462;
  c.cx = 318;
  c.cy = 243;
  c.dist = {-0.12, 0.03, 0.001, -0.0005, 0.0};
  c.R_CtoB << 0, 1, 0, -1, 0, 0, 0, 0, 1;  // looking up
  c.p_CinB = Eigen::Vector3d(0.08, -0.03, 0.12);  // a lever arm
  return c;
}

Eigen::Matrix3d attitude(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

LedSighting sight(const CameraModel& cam, const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const Eigen::Vector3d& L) {
  const auto uv = predict_pixel(cam, R, p, L);
  REQUIRE(uv);
  return {L, *uv};
}

}  // namespace

TEST_CASE("camera height: two LEDs give the body height exactly, whatever the yaw and the position", "[vlc][height]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.7, 0.04, -0.06);
  for (const double z : {0.4, 1.1, 1.9}) {
    const Eigen::Vector3d p(2.1, 1.7, z);
    const std::vector<LedSighting> leds = {sight(cam, R, p, {1.6, 1.2, 3.0}), sight(cam, R, p, {2.9, 2.2, 3.0})};
    const auto h = camera_height(leds, cam, R, std::numeric_limits<double>::quiet_NaN());
    REQUIRE(h);
    CHECK(h->z_m == Approx(z).margin(1e-6));
    CHECK(h->sigma_m > 0.0);
    CHECK(h->sigma_m < 0.1);
    // A wrong yaw turns both rays together: their angle and elevations stay, so the height does.
    const auto turned = camera_height(leds, cam, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * R, z);
    REQUIRE(turned);
    CHECK(turned->z_m == Approx(z).margin(1e-6));
  }
}

TEST_CASE("camera height: LEDs at different heights, the hint picks the root", "[vlc][height]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(-1.2, 0.0, 0.02);
  const Eigen::Vector3d p(3.0, 2.0, 1.0);
  const std::vector<LedSighting> leds = {sight(cam, R, p, {2.4, 1.5, 2.6}), sight(cam, R, p, {3.9, 2.4, 3.4})};
  const auto h = camera_height(leds, cam, R, 1.2);
  REQUIRE(h);
  CHECK(h->z_m == Approx(1.0).margin(1e-6));
  // With three LEDs the best pair (smallest sigma) is used, still exact.
  std::vector<LedSighting> three = leds;
  three.push_back(sight(cam, R, p, {3.2, 2.6, 3.0}));
  const auto h3 = camera_height(three, cam, R, 1.2);
  REQUIRE(h3);
  CHECK(h3->z_m == Approx(1.0).margin(1e-6));
  CHECK(h3->sigma_m <= h->sigma_m + 1e-12);
}

TEST_CASE("camera height: refused with one LED, or a pair too close in the image", "[vlc][height]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d p(2.0, 2.0, 1.0);
  CHECK_FALSE(camera_height({sight(cam, R, p, {2.0, 2.0, 3.0})}, cam, R, 1.0));
  // 0.1 m apart, 2 m away: 0.05 rad < min_pair_angle_rad.
  CHECK_FALSE(camera_height({sight(cam, R, p, {2.0, 2.0, 3.0}), sight(cam, R, p, {2.1, 2.0, 3.0})}, cam, R, 1.0));
}

TEST_CASE("camera height: the sigma matches the scatter under pixel noise", "[vlc][height]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.3, 0.0, 0.0);
  const Eigen::Vector3d p(2.0, 2.0, 1.2);
  const std::vector<LedSighting> clean = {sight(cam, R, p, {1.2, 1.6, 3.0}), sight(cam, R, p, {3.0, 2.3, 3.0})};
  CameraHeightOptions o;
  o.pixel_sigma = 1.0;
  o.attitude_sigma_rad = 1e-9;  // pixel noise only
  std::mt19937_64 rng(7);
  std::normal_distribution<double> px(0.0, 1.0);
  double sum2 = 0.0, sigma = 0.0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    std::vector<LedSighting> noisy = clean;
    for (LedSighting& s : noisy) s.uv += Eigen::Vector2d(px(rng), px(rng));
    const auto h = camera_height(noisy, cam, R, 1.2, o);
    REQUIRE(h);
    sum2 += (h->z_m - 1.2) * (h->z_m - 1.2);
    sigma += h->sigma_m / n;
  }
  const double rms = std::sqrt(sum2 / n);
  INFO("scatter " << rms << " m, sigma " << sigma << " m");
  CHECK(rms == Approx(sigma).epsilon(0.15));
}

TEST_CASE("disc height: one LED of known diameter gives the height from its apparent size", "[vlc][height]") {
  const CameraModel cam = camera_up();
  const Eigen::Matrix3d R = attitude(0.5, -0.03, 0.05);
  const Eigen::Vector3d L(2.5, 1.8, 3.0);
  for (const double z : {0.6, 1.4}) {
    const Eigen::Vector3d p(2.0, 2.1, z);
    const LedSighting s = sight(cam, R, p, L);
    // The disc's true apparent radius: projected at its true place.
    const Eigen::Matrix3d R_WtoC = (R * cam.R_CtoB).transpose();
    const Eigen::Vector3d c_inW = p + R * cam.p_CinB;
    const double r = projected_disc_radius_px(cam, R_WtoC, R_WtoC * (L - c_inW), 0.1);
    REQUIRE(r > 5.0);
    const auto h = disc_height(DiscSighting{L, s.uv, r, 0.2}, cam, R);
    REQUIRE(h);
    CHECK(h->z_m == Approx(z).margin(2e-3));
    // A blob 5 % too large reads the LED 5 % nearer: the camera higher by ~5 % of the range.
    const auto big = disc_height(DiscSighting{L, s.uv, 1.05 * r, 0.2}, cam, R);
    REQUIRE(big);
    const double range_z = L.z() - c_inW.z();
    CHECK(big->z_m - z == Approx(range_z * (1.0 - 1.0 / 1.05)).epsilon(0.05));
    CHECK(h->sigma_m == Approx(range_z * (0.5 / r + 0.02)).epsilon(0.3));
  }
  // No size, no diameter, or a ray that does not rise: no height.
  const LedSighting s = sight(cam, R, {2.0, 2.1, 1.0}, L);
  CHECK_FALSE(disc_height(DiscSighting{L, s.uv, 0.0, 0.2}, cam, R));
  CHECK_FALSE(disc_height(DiscSighting{L, s.uv, 20.0, 0.0}, cam, R));
  CHECK_FALSE(disc_height(DiscSighting{L, s.uv, 20.0, 0.2}, cam, attitude(0.0, 3.1, 0.0)));
}
