#pragma once
// Tight coupling (issue: VLC): a particle at (x, y) predicts where each decoded LED should
// appear in the image; the log-likelihood is the robust (Huber-like, Cauchy tail) sum of
// squared pixel errors. One visible LED then still corrects the filter, where a loose fix
// needs the positioner to succeed first.
#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <vector>

#include "core/vlc/camera_model.hpp"

namespace luxloc {

struct ReprojectionTerm {
  Eigen::Vector3d p_LinW;   // LED position (world)
  Eigen::Vector2d uv;       // observed centre (distorted pixels)
  double inv_var = 1.0;     // 1 / sigma_px^2
};

class ReprojectionLikelihood {
 public:
  // R_BtoW: attitude at the observation time; z_B: body height (m).
  ReprojectionLikelihood(const CameraModel& camera, const Eigen::Matrix3d& R_BtoW, double z_B,
                         std::vector<ReprojectionTerm> terms, double outlier_px = 25.0)
      : camera_(camera), terms_(std::move(terms)), z_B_(z_B) {
    M_ = camera.R_CtoB.transpose() * R_BtoW.transpose();  // world offset -> camera frame
    offset_ = camera.R_CtoB.transpose() * camera.p_CinB;
    outlier2_ = outlier_px * outlier_px;
  }

  // log p(observations | body at (x, y, z_B), yaw offset e), up to a constant. The true
  // attitude is Rz(e) R_BtoW (the particle's yaw offset of the AHRS, heading_noise.hpp), so
  // a world offset reaches the camera as M Rz(-e) (p_L - p_B).
  double operator()(double x, double y, double e = 0.0) const {
    const double c = std::cos(e), s = std::sin(e);
    double ll = 0.0;
    for (const ReprojectionTerm& t : terms_) {
      const Eigen::Vector3d d = t.p_LinW - Eigen::Vector3d(x, y, z_B_);
      const Eigen::Vector3d p_LinC = M_ * Eigen::Vector3d(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()) - offset_;
      Eigen::Vector2d uv;
      if (!camera_.project(p_LinC, uv)) {
        ll -= 0.5 * outlier2_ * t.inv_var;
        continue;
      }
      const double e2 = (uv - t.uv).squaredNorm();
      // Gaussian near the observation, flattened beyond outlier_px so one wrong blob
      // cannot wipe out the right particles (a Cauchy-like tail).
      ll -= 0.5 * t.inv_var * (e2 < outlier2_ ? e2 : outlier2_ * (1.0 + std::log(e2 / outlier2_)));
    }
    return ll;
  }

  // Mean pixel error at (x, y) and yaw offset e: for gating.
  double rms_px(double x, double y, double e = 0.0) const {
    const double ce = std::cos(e), se = std::sin(e);
    double s = 0.0;
    int n = 0;
    for (const ReprojectionTerm& t : terms_) {
      Eigen::Vector2d uv;
      const Eigen::Vector3d d = t.p_LinW - Eigen::Vector3d(x, y, z_B_);
      if (!camera_.project(M_ * Eigen::Vector3d(ce * d.x() + se * d.y(), -se * d.x() + ce * d.y(), d.z()) - offset_, uv))
        return 1e9;
      s += (uv - t.uv).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(s / n) : 0.0;
  }
  std::size_t size() const { return terms_.size(); }

  // Inverse of the model for initialisation: the body (x, y) that puts term i's LED exactly
  // on its observed pixel (the bearing ray meets the LED's height above z_B). nullopt when
  // the ray does not point up towards the LED plane.
  std::optional<Eigen::Vector2d> invert(std::size_t i) const {
    const ReprojectionTerm& t = terms_[i];
    const Eigen::Vector3d ray_inW = M_.transpose() * camera_.bearing(t.uv);  // camera -> world
    const Eigen::Vector3d p_CinW_rel = M_.transpose() * offset_;              // camera lever arm, world
    const double dz = t.p_LinW.z() - (z_B_ + p_CinW_rel.z());
    if (ray_inW.z() < 0.05 || dz <= 0.0) return std::nullopt;
    const Eigen::Vector3d p_CinW = t.p_LinW - ray_inW * (dz / ray_inW.z());
    return Eigen::Vector2d(p_CinW.x() - p_CinW_rel.x(), p_CinW.y() - p_CinW_rel.y());
  }

 private:
  const CameraModel& camera_;
  std::vector<ReprojectionTerm> terms_;
  Eigen::Matrix3d M_;
  Eigen::Vector3d offset_;
  double z_B_;
  double outlier2_;
};

}  // namespace luxloc
