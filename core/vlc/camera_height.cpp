#include "core/vlc/camera_height.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace luxloc {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Height of the camera centre from the pair's world rays (unit) and LED positions; NaN
// when no root has both ranges positive.
double pair_camera_z(const Eigen::Vector3d& d1, const Eigen::Vector3d& d2, const Eigen::Vector3d& L1,
                     const Eigen::Vector3d& L2, double z_hint_camera) {
  // t2 = (t1 d1z - dz) / d2z; | t1 a + b | = S with a = d1 - d2 d1z / d2z, b = d2 dz / d2z.
  const double dz = L1.z() - L2.z();
  const double S2 = (L1 - L2).squaredNorm();
  const Eigen::Vector3d a = d1 - d2 * (d1.z() / d2.z());
  const Eigen::Vector3d b = d2 * (dz / d2.z());
  const double A = a.squaredNorm(), B = 2.0 * a.dot(b), C = b.squaredNorm() - S2;
  if (!(A > 1e-12)) return kNaN;
  const double disc = B * B - 4.0 * A * C;
  if (disc < 0.0) return kNaN;
  const double q = std::sqrt(disc);
  double best = kNaN;
  for (const double t1 : {(-B + q) / (2.0 * A), (-B - q) / (2.0 * A)}) {
    const double t2 = (t1 * d1.z() - dz) / d2.z();
    if (!(t1 > 0.0) || !(t2 > 0.0)) continue;
    const double z = L1.z() - t1 * d1.z();
    if (std::isnan(best)) {
      best = z;
    } else if (std::isfinite(z_hint_camera)) {
      if (std::abs(z - z_hint_camera) < std::abs(best - z_hint_camera)) best = z;
    } else {
      best = std::min(best, z);
    }
  }
  return best;
}

Eigen::Matrix3d tilt(double rx, double ry) {
  return (Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()))
      .toRotationMatrix();
}

}  // namespace

std::optional<CameraHeight> camera_height(const std::vector<LedSighting>& leds, const CameraModel& camera,
                                          const Eigen::Matrix3d& R_BtoW, double z_hint_m,
                                          const CameraHeightOptions& o) {
  if (leds.size() < 2 || !R_BtoW.allFinite()) return std::nullopt;
  const Eigen::Vector3d lever = R_BtoW * camera.p_CinB;  // camera centre - body origin (world)
  const double hint_c = std::isfinite(z_hint_m) ? z_hint_m + lever.z() : kNaN;
  // Body height of pair (i, j) with the pixels and the attitude as given.
  const auto solve = [&](const Eigen::Vector2d& ui, const Eigen::Vector2d& uj, std::size_t i, std::size_t j,
                         const Eigen::Matrix3d& R) {
    const Eigen::Matrix3d R_CtoW = R * camera.R_CtoB;
    const Eigen::Vector3d di = (R_CtoW * camera.bearing(ui)).normalized();
    const Eigen::Vector3d dj = (R_CtoW * camera.bearing(uj)).normalized();
    if (!(di.z() >= o.min_ray_elevation) || !(dj.z() >= o.min_ray_elevation)) return kNaN;
    return pair_camera_z(di, dj, leds[i].p_LinW, leds[j].p_LinW, hint_c) - (R * camera.p_CinB).z();
  };
  std::optional<CameraHeight> best;
  for (std::size_t i = 0; i < leds.size(); ++i)
    for (std::size_t j = i + 1; j < leds.size(); ++j) {
      const LedSighting& a = leds[i];
      const LedSighting& b = leds[j];
      if (!a.uv.allFinite() || !b.uv.allFinite() || !a.p_LinW.allFinite() || !b.p_LinW.allFinite()) continue;
      const double angle = std::acos(std::clamp(camera.bearing(a.uv).normalized().dot(camera.bearing(b.uv).normalized()), -1.0, 1.0));
      if (!(angle >= o.min_pair_angle_rad)) continue;
      const double z = solve(a.uv, b.uv, i, j, R_BtoW);
      if (!std::isfinite(z)) continue;
      // Finite differences: half a pixel on each coordinate, a milliradian of tilt.
      double var = 0.0;
      const double hp = 0.5;
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector2d ua = a.uv, ub = b.uv;
        (k < 2 ? ua : ub)(k % 2) += hp;
        const double zk = solve(ua, ub, i, j, R_BtoW);
        if (!std::isfinite(zk)) {
          var = kNaN;
          break;
        }
        const double g = (zk - z) / hp;
        var += g * g * o.pixel_sigma * o.pixel_sigma;
      }
      const double ht = 1e-3;
      for (int k = 0; k < 2 && std::isfinite(var); ++k) {
        const double zk = solve(a.uv, b.uv, i, j, tilt(k == 0 ? ht : 0.0, k == 1 ? ht : 0.0) * R_BtoW);
        if (!std::isfinite(zk)) {
          var = kNaN;
          break;
        }
        const double g = (zk - z) / ht;
        var += g * g * o.attitude_sigma_rad * o.attitude_sigma_rad;
      }
      if (!std::isfinite(var)) continue;
      const double sigma = std::sqrt(var);
      if (!best || sigma < best->sigma_m)
        best = CameraHeight{z, sigma, static_cast<int>(i), static_cast<int>(j)};
    }
  return best;
}

double projected_disc_radius_px(const CameraModel& camera, const Eigen::Matrix3d& R_WtoC,
                                const Eigen::Vector3d& centre_inC, double radius_m) {
  const Eigen::Vector3d ex = R_WtoC.col(0), ey = R_WtoC.col(1);
  constexpr int kPoints = 32;
  std::array<Eigen::Vector2d, kPoints> uv;
  for (int k = 0; k < kPoints; ++k) {
    const double a = 2.0 * 3.14159265358979323846 * k / kPoints;
    if (!camera.project(centre_inC + radius_m * (std::cos(a) * ex + std::sin(a) * ey), uv[static_cast<std::size_t>(k)]))
      return kNaN;
  }
  double area2 = 0.0;  // shoelace
  for (std::size_t k = 0; k < uv.size(); ++k) {
    const Eigen::Vector2d& p = uv[k];
    const Eigen::Vector2d& q = uv[(k + 1) % uv.size()];
    area2 += p.x() * q.y() - q.x() * p.y();
  }
  return std::sqrt(std::abs(area2) / 2.0 / 3.14159265358979323846);
}

std::optional<CameraHeight> disc_height(const DiscSighting& led, const CameraModel& camera,
                                        const Eigen::Matrix3d& R_BtoW, const CameraHeightOptions& o) {
  if (!(led.radius_px > 1.0) || !(led.diameter_m > 0.0) || !led.uv.allFinite() || !led.p_LinW.allFinite() ||
      !R_BtoW.allFinite())
    return std::nullopt;
  const Eigen::Matrix3d R_CtoW = R_BtoW * camera.R_CtoB;
  const Eigen::Vector3d b_inC = camera.bearing(led.uv).normalized();
  const Eigen::Vector3d d = R_CtoW * b_inC;
  if (!(d.z() >= o.min_ray_elevation)) return std::nullopt;
  // r(t) ~ 1 / t for a disc small against its range: two steps of t <- t r(t) / r.
  double t = 2.0;
  for (int k = 0; k < 2; ++k) {
    const double r = projected_disc_radius_px(camera, R_CtoW.transpose(), b_inC * t, 0.5 * led.diameter_m);
    if (!std::isfinite(r) || !(r > 0.0)) return std::nullopt;
    t *= r / led.radius_px;
  }
  if (!(t > 0.0) || !std::isfinite(t)) return std::nullopt;
  const double z = led.p_LinW.z() - t * d.z() - (R_BtoW * camera.p_CinB).z();
  const double rel = o.radius_sigma_px / led.radius_px + o.radius_rel_sigma;
  // The range's relative error times the vertical range; the tilt moves the ray's
  // elevation by attitude_sigma: t |d_xy| sigma_att.
  const double sigma = std::hypot(t * d.z() * rel, t * d.head<2>().norm() * o.attitude_sigma_rad);
  return CameraHeight{z, sigma, 0, -1};
}

}  // namespace luxloc
