#pragma once
// The independent check of a frequency plan (issue 14), shared by the planner's tests and
// the `calib ledmap plan` CLI tests: poses with two LEDs of one class in the image, out of
// `samples` drawn over the LEDs' floor box grown by 1 m (the camera at device height
// looking up, any yaw, tilted up to max_tilt about a random horizontal axis). Uses only
// CameraModel::project, none of the planner's geometry.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_visibility.hpp"

namespace luxloc::test {

inline int views_with_two_of_a_class(const std::vector<Eigen::Vector3d>& p_inW, const std::vector<int>& klass,
                                     const CameraModel& cam, double device_z, double max_tilt, int samples,
                                     std::uint64_t seed) {
  constexpr double kPi = 3.14159265358979323846;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Vector2d lo = p_inW.front().head<2>(), hi = lo;
  for (const auto& q : p_inW) {
    lo = lo.cwiseMin(q.head<2>());
    hi = hi.cwiseMax(q.head<2>());
  }
  Eigen::Matrix3d R0;  // camera x = world y, camera y = world -x, camera z = up
  R0.col(0) = Eigen::Vector3d::UnitY();
  R0.col(1) = -Eigen::Vector3d::UnitX();
  R0.col(2) = Eigen::Vector3d::UnitZ();
  // Beyond the image diagonal's angle the distortion polynomial folds points back into the
  // image (r (1 + k1 r^2) turns over): such points are not seen, whatever project() says.
  const double max_angle = half_diagonal_fov_rad(cam) + 1e-3;
  int bad = 0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d c(lo.x() - 1 + (hi.x() - lo.x() + 2) * u(rng), lo.y() - 1 + (hi.y() - lo.y() + 2) * u(rng),
                            device_z);
    const double yaw = 2 * kPi * u(rng), tilt = max_tilt * std::sqrt(u(rng)), axis = 2 * kPi * u(rng);
    const Eigen::Matrix3d R_CtoW =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)).toRotationMatrix() * R0;
    std::map<int, int> seen;
    for (std::size_t i = 0; i < p_inW.size(); ++i) {
      const Eigen::Vector3d p_inC = R_CtoW.transpose() * (p_inW[i] - c);
      Eigen::Vector2d uv;
      if (std::atan2(p_inC.head<2>().norm(), p_inC.z()) > max_angle || !cam.project(p_inC, uv)) continue;
      if (uv.x() < 0 || uv.y() < 0 || uv.x() >= cam.width || uv.y() >= cam.height) continue;
      if (++seen[klass[i]] == 2) {
        ++bad;
        break;
      }
    }
  }
  return bad;
}

// The same for a map: its LEDs' positions and frequency classes.
inline int views_with_two_of_a_class(const LedMap& map, const CameraModel& cam, double device_z, double max_tilt,
                                     int samples, std::uint64_t seed) {
  std::vector<Eigen::Vector3d> p;
  std::vector<int> klass;
  for (std::size_t i = 0; i < map.size(); ++i) {
    p.push_back(map.leds()[i].p_inW);
    klass.push_back(map.class_of(i));
  }
  return views_with_two_of_a_class(p, klass, cam, device_z, max_tilt, samples, seed);
}

}  // namespace luxloc::test
