#include "core/vlc/camera_geometry_fix.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace luxloc {
namespace {

bool is_rotation(const Eigen::Matrix3d& R) {
  return R.allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-3 && R.determinant() > 0.0;
}

double rms_reprojection(const std::vector<LedSighting>& leds, const CameraModel& camera, const Eigen::Matrix3d& R_BtoW,
                        const Eigen::Vector3d& p_BinW) {
  double s = 0.0;
  for (const LedSighting& l : leds) {
    const auto uv = predict_pixel(camera, R_BtoW, p_BinW, l.p_LinW);
    if (!uv) return std::numeric_limits<double>::infinity();
    s += (*uv - l.uv).squaredNorm();
  }
  return leds.empty() ? 0.0 : std::sqrt(s / static_cast<double>(leds.size()));
}

// Camera centre from LED rays (world directions d_i through LED positions L_i): the point
// closest to all rays, each perpendicular distance divided by its range (so every LED
// counts by angle). z_cam finite and !solve_z: the height is fixed.
bool solve_camera_centre(const std::vector<LedSighting>& leds, const std::vector<Eigen::Vector3d>& rays,
                         double z_cam, bool solve_z, const CameraFixOptions& o, Eigen::Vector3d& p) {
  const std::size_t n = leds.size();
  for (const auto& d : rays)
    if (!(d.z() >= o.min_ray_elevation)) return false;  // not rising towards a ceiling LED
  const bool fixed_z = std::isfinite(z_cam) && !solve_z;
  if (fixed_z) {
    // Start: each ray meets its LED's height above the camera; their mean.
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const double dz = leds[i].p_LinW.z() - z_cam;
      if (!(dz > 0.0)) return false;  // LED not above the camera
      mean += (leds[i].p_LinW - rays[i] * (dz / rays[i].z())).head<2>();
    }
    p = Eigen::Vector3d(mean.x() / static_cast<double>(n), mean.y() / static_cast<double>(n), z_cam);
    if (n == 1) return p.allFinite();
  } else {
    if (n < 2) return false;
    p = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) p += leds[i].p_LinW - rays[i];  // 1 m below each LED along its ray
    p /= static_cast<double>(n);
  }
  for (int it = 0; it < 3; ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - rays[i] * rays[i].transpose();
      const double w = 1.0 / std::max((leds[i].p_LinW - p).squaredNorm(), 1e-6);
      A += w * P;
      b += w * P * leds[i].p_LinW;
    }
    if (fixed_z) {
      const Eigen::Matrix2d A2 = A.topLeftCorner<2, 2>();
      const Eigen::Vector2d b2 = b.head<2>() - A.topRightCorner<2, 1>() * z_cam;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(A2);
      if (!(es.eigenvalues()(0) > 1e-9 * std::max(es.eigenvalues()(1), 1e-300))) return false;
      p.head<2>() = A2.ldlt().solve(b2);
    } else {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
      // Rays that are (nearly) parallel do not fix the distance along them.
      if (!(es.eigenvalues()(0) > 1e-6 * std::max(es.eigenvalues()(2), 1e-300))) return false;
      p = A.ldlt().solve(b);
    }
    if (!p.allFinite()) return false;
  }
  return true;
}

struct BearingInputs {
  std::vector<LedSighting> leds;
  Eigen::Matrix3d R_BtoW;
  double height;
};

// The whole bearing solve as a function of its noisy inputs (for the propagation).
bool bearing_solve(const BearingInputs& in, const CameraModel& camera, const CameraFixOptions& o, bool solve_z,
                   Eigen::Vector3d& p_BinW) {
  const Eigen::Matrix3d R_CtoW = in.R_BtoW * camera.R_CtoB;
  std::vector<Eigen::Vector3d> rays;
  rays.reserve(in.leds.size());
  for (const LedSighting& l : in.leds) rays.push_back(R_CtoW * camera.bearing(l.uv));
  const Eigen::Vector3d lever_inW = in.R_BtoW * camera.p_CinB;
  const double z_cam = std::isfinite(in.height) ? in.height + lever_inW.z() : std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d p_CinW;
  if (!solve_camera_centre(in.leds, rays, z_cam, solve_z, o, p_CinW)) return false;
  p_BinW = p_CinW - lever_inW;
  return p_BinW.allFinite();
}

Eigen::Matrix3d small_rotation(int axis, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

}  // namespace

std::vector<LedSighting> sightings_from(const std::vector<LedObservation>& observations, const LedMap& map,
                                        bool use_border_blobs) {
  std::vector<LedSighting> out;
  for (const LedObservation& o : observations) {
    if (!o.accepted() || o.led_index >= static_cast<int>(map.size())) continue;
    if (o.touches_border && !use_border_blobs) continue;
    if (!o.uv.allFinite()) continue;
    out.push_back({map.leds()[static_cast<std::size_t>(o.led_index)].p_inW, o.uv});
  }
  return out;
}

VlcFix bearing_fix(const std::vector<LedSighting>& leds, const CameraModel& camera, const Eigen::Matrix3d& R_BtoW,
                   double device_height_m, const CameraFixOptions& o) {
  VlcFix fix;
  fix.method = VlcFix::Method::Bearing;
  fix.n_leds = static_cast<int>(leds.size());
  if (!is_rotation(R_BtoW) || leds.empty()) return fix;
  for (const LedSighting& l : leds)
    if (!l.p_LinW.allFinite() || !l.uv.allFinite()) return fix;
  fix.R_BtoW = R_BtoW;
  const bool height_known = std::isfinite(device_height_m);
  // Solve z too when the height is unknown, or when asked and the LEDs subtend enough angle.
  bool solve_z = !height_known;
  if (height_known && o.solve_height && leds.size() >= 2) {
    double max_angle = 0.0;
    for (std::size_t i = 0; i < leds.size(); ++i)
      for (std::size_t j = i + 1; j < leds.size(); ++j) {
        const Eigen::Vector3d a = camera.bearing(leds[i].uv), b = camera.bearing(leds[j].uv);
        max_angle = std::max(max_angle, std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
      }
    solve_z = max_angle >= o.min_height_baseline;
  }
  BearingInputs in{leds, R_BtoW, height_known ? device_height_m : std::numeric_limits<double>::quiet_NaN()};
  Eigen::Vector3d p;
  if (!bearing_solve(in, camera, o, solve_z, p)) return fix;
  fix.p_BinW = p;
  fix.residual_px = rms_reprojection(leds, camera, R_BtoW, p);

  // First-order covariance by central differences through the solver.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  auto add = [&](BearingInputs plus, BearingInputs minus, double step, double sigma) {
    Eigen::Vector3d pp, pm;
    if (!bearing_solve(plus, camera, o, solve_z, pp) || !bearing_solve(minus, camera, o, solve_z, pm)) return false;
    const Eigen::Vector3d J = (pp - pm) / (2.0 * step);
    cov += sigma * sigma * J * J.transpose();
    return true;
  };
  bool ok = true;
  constexpr double kPx = 0.25, kRad = 1e-4, kM = 1e-3;
  for (std::size_t i = 0; i < leds.size() && ok; ++i)
    for (int k = 0; k < 2 && ok; ++k) {
      BearingInputs a = in, b = in;
      a.leds[i].uv(k) += kPx;
      b.leds[i].uv(k) -= kPx;
      ok = add(a, b, kPx, o.pixel_sigma);
    }
  for (int axis = 0; axis < 3 && ok; ++axis) {
    BearingInputs a = in, b = in;
    a.R_BtoW = small_rotation(axis, kRad) * R_BtoW;
    b.R_BtoW = small_rotation(axis, -kRad) * R_BtoW;
    ok = add(a, b, kRad, o.attitude_sigma_rad);
  }
  if (ok && height_known && !solve_z) {
    BearingInputs a = in, b = in;
    a.height += kM;
    b.height -= kM;
    ok = add(a, b, kM, o.height_sigma_m);
  }
  if (!ok || !cov.allFinite()) return fix;
  fix.cov_xy = cov.topLeftCorner<2, 2>();
  fix.sigma_z = solve_z ? std::sqrt(std::max(0.0, cov(2, 2))) : 0.0;
  fix.valid = fix.residual_px <= o.max_residual_px;
  return fix;
}

VlcFix bearing_fix(const std::vector<LedObservation>& observations, const LedMap& map, const CameraModel& camera,
                   const Eigen::Matrix3d& R_BtoW, double device_height_m, const CameraFixOptions& options) {
  return bearing_fix(sightings_from(observations, map, options.use_border_blobs), camera, R_BtoW, device_height_m,
                     options);
}

namespace {

// World pose of the body from OpenCV's world->camera (rvec, tvec).
void body_pose_from(const cv::Vec3d& rvec, const cv::Vec3d& tvec, const CameraModel& camera, Eigen::Matrix3d& R_BtoW,
                    Eigen::Vector3d& p_BinW) {
  cv::Matx33d Rcv;
  cv::Rodrigues(rvec, Rcv);
  Eigen::Matrix3d R_WtoC;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_WtoC(r, c) = Rcv(r, c);
  const Eigen::Matrix3d R_CtoW = R_WtoC.transpose();
  const Eigen::Vector3d p_CinW = -R_CtoW * Eigen::Vector3d(tvec[0], tvec[1], tvec[2]);
  R_BtoW = R_CtoW * camera.R_CtoB.transpose();
  p_BinW = p_CinW - R_BtoW * camera.p_CinB;
}

}  // namespace

VlcFix pnp_fix(const std::vector<LedSighting>& leds, const CameraModel& camera, const CameraFixOptions& o) {
  VlcFix fix;
  fix.method = VlcFix::Method::Pnp;
  fix.n_leds = static_cast<int>(leds.size());
  if (leds.size() < 3) return fix;
  std::vector<cv::Point3d> obj;
  std::vector<cv::Point2d> img;
  for (const LedSighting& l : leds) {
    if (!l.p_LinW.allFinite() || !l.uv.allFinite()) return fix;
    obj.emplace_back(l.p_LinW.x(), l.p_LinW.y(), l.p_LinW.z());
    img.emplace_back(l.uv.x(), l.uv.y());
  }
  // Degenerate layouts: LEDs (nearly) collinear give no pose.
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const LedSighting& l : leds) c += l.p_LinW;
  c /= static_cast<double>(leds.size());
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const LedSighting& l : leds) S += (l.p_LinW - c) * (l.p_LinW - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
  const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);
  if (!(ev(1) > 1e-6 * std::max(ev(2), 1e-12))) return fix;
  const bool coplanar = ev(0) <= 1e-8 * ev(2);

  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(camera.dist.data()));
  cv::Vec3d rvec, tvec;
  try {
    const int method = (coplanar && leds.size() >= 4) ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_SQPNP;
    if (!cv::solvePnP(obj, img, K, D, rvec, tvec, false, method)) return fix;
    if (leds.size() >= 4) cv::solvePnPRefineLM(obj, img, K, D, rvec, tvec);
  } catch (const cv::Exception&) {
    return fix;
  }
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  body_pose_from(rvec, tvec, camera, R, p);
  if (!p.allFinite() || !is_rotation(R)) return fix;
  fix.R_BtoW = R;
  fix.p_BinW = p;
  fix.residual_px = rms_reprojection(leds, camera, R, p);
  if (!std::isfinite(fix.residual_px)) return fix;

  // Pose covariance sigma^2 (J^T J)^-1 from the projection Jacobian wrt (rvec, tvec), then
  // to the body position by central differences of the closed-form pose.
  std::vector<cv::Point2d> proj;
  cv::Mat J;
  cv::projectPoints(obj, rvec, tvec, K, D, proj, J);
  Eigen::MatrixXd Je(J.rows, 6);
  for (int r = 0; r < J.rows; ++r)
    for (int k = 0; k < 6; ++k) Je(r, k) = J.at<double>(r, k);
  const Eigen::Matrix<double, 6, 6> info = Je.transpose() * Je;
  const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(info);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  if (lu.isInvertible()) {
    const Eigen::Matrix<double, 6, 6> Sigma = o.pixel_sigma * o.pixel_sigma * lu.inverse();
    Eigen::Matrix<double, 3, 6> G;
    constexpr double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      cv::Vec3d rp = rvec, rm = rvec, tp = tvec, tm = tvec;
      if (k < 3) {
        rp[k] += h;
        rm[k] -= h;
      } else {
        tp[k - 3] += h;
        tm[k - 3] -= h;
      }
      Eigen::Matrix3d Ra, Rb;
      Eigen::Vector3d pa, pb;
      body_pose_from(rp, tp, camera, Ra, pa);
      body_pose_from(rm, tm, camera, Rb, pb);
      G.col(k) = (pa - pb) / (2 * h);
    }
    cov = G * Sigma * G.transpose();
  } else {
    return fix;  // the pose is not determined
  }
  if (!cov.allFinite()) return fix;
  fix.cov_xy = cov.topLeftCorner<2, 2>();
  fix.sigma_z = std::sqrt(std::max(0.0, cov(2, 2)));
  fix.valid = fix.residual_px <= o.max_residual_px;
  return fix;
}

VlcFix pnp_fix(const std::vector<LedObservation>& observations, const LedMap& map, const CameraModel& camera,
               const CameraFixOptions& options) {
  return pnp_fix(sightings_from(observations, map, options.use_border_blobs), camera, options);
}

}  // namespace luxloc
