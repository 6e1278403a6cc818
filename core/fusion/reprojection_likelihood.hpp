#pragma once
// Tight coupling (issue: VLC): a particle at (x, y) predicts where each decoded LED should
// appear in the image; the log-likelihood is the robust (Huber-like, Cauchy tail) sum of
// squared pixel errors. One visible LED then still corrects the filter, where a loose fix
// needs the positioner to succeed first.
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_class_index.hpp"

namespace luxloc {

struct ReprojectionTerm {
  Eigen::Vector3d p_LinW;   // LED position (world); unused while `klass` >= 0
  Eigen::Vector2d uv;       // observed centre (distorted pixels)
  double inv_var = 1.0;     // 1 / sigma_px^2
  // A reused frequency (issue 14): the class whose copies the particle chooses among, the
  // one its own pose puts nearest the observed bearing; -1 when the LED is known.
  int klass = -1;
};

// Per-particle association of reused frequencies: the map's class index and, per class,
// the ceiling height the bearing is met at.
struct ReuseAssociation {
  const LedMap* map = nullptr;
  const LedClassIndex* index = nullptr;
};

class ReprojectionLikelihood {
 public:
  // R_BtoW: attitude at the observation time; z_B: body height (m).
  ReprojectionLikelihood(const CameraModel& camera, const Eigen::Matrix3d& R_BtoW, double z_B,
                         std::vector<ReprojectionTerm> terms, double outlier_px = 25.0, ReuseAssociation reuse = {})
      : camera_(camera), terms_(std::move(terms)), z_B_(z_B), reuse_(reuse) {
    M_ = camera.R_CtoB.transpose() * R_BtoW.transpose();  // world offset -> camera frame
    offset_ = camera.R_CtoB.transpose() * camera.p_CinB;
    outlier2_ = outlier_px * outlier_px;
    // Association (issue 14): the bearing of a reused class meets the class's ceiling at
    // p_B + Rz(e) w, with w = M^T (lambda b + offset) fixed for the frame (z_B is): so a
    // particle finds its copy with one turn by e and one grid lookup.
    ceiling_.assign(terms_.size(), Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (std::size_t i = 0; i < terms_.size(); ++i) {
      const ReprojectionTerm& t = terms_[i];
      if (t.klass < 0 || !reuse_.map) continue;
      const Eigen::Vector3d ray = M_.transpose() * camera_.bearing(t.uv);
      const Eigen::Vector3d c0 = M_.transpose() * offset_;
      const double dz = reuse_.map->classes()[static_cast<std::size_t>(t.klass)].mean_z - (z_B_ + c0.z());
      if (ray.z() < 0.05 || dz <= 0.0) continue;  // not pointing up at the ceiling: no association
      ceiling_[i] = (c0 + ray * (dz / ray.z())).head<2>();
    }
  }

  // The LED term i stands for as seen from a particle at (x, y, e): the known LED, or the
  // copy of its class nearest the bearing's ceiling point within the class's capture
  // radius (half its reuse distance); nullptr when none.
  const Eigen::Vector3d* led_for(std::size_t i, double x, double y, double c, double s) const {
    const ReprojectionTerm& t = terms_[i];
    if (t.klass < 0) return &t.p_LinW;
    const int k = copy_for(i, x, y, c, s);
    return k < 0 ? nullptr : &reuse_.map->leds()[static_cast<std::size_t>(k)].p_inW;
  }
  // The copy (index into the map) a reused term i is associated with at (x, y, e); -1 when
  // none, or when the term's LED is known (no choice to make).
  int associate(std::size_t i, double x, double y, double e = 0.0) const {
    return terms_[i].klass < 0 ? -1 : copy_for(i, x, y, std::cos(e), std::sin(e));
  }
  const ReprojectionTerm& term(std::size_t i) const { return terms_[i]; }
  // Where reused term i's bearing meets its class's ceiling, relative to the body at yaw
  // offset 0 (the particle at (x, y, e) looks at (x, y) + Rz(e) w); NaN when it does not
  // point up at the ceiling or the LED is known.
  const Eigen::Vector2d& ceiling_point(std::size_t i) const { return ceiling_[i]; }
  // A copy with every reused term replaced by its association at (x, y, e) (the EKF's and
  // the loose fix's single hypothesis); unassociated reused terms are dropped.
  ReprojectionLikelihood resolved(double x, double y, double e, std::size_t* dropped = nullptr) const {
    std::vector<ReprojectionTerm> fixed;
    std::size_t lost = 0;
    const double c = std::cos(e), s = std::sin(e);
    const bool at_pose = std::isfinite(x) && std::isfinite(y) && std::isfinite(e);  // NaN: drop every reused term
    for (std::size_t i = 0; i < terms_.size(); ++i) {
      const Eigen::Vector3d* p = terms_[i].klass < 0 || at_pose ? led_for(i, x, y, c, s) : nullptr;
      if (!p) {
        ++lost;
        continue;
      }
      ReprojectionTerm t = terms_[i];
      t.p_LinW = *p;
      t.klass = -1;
      fixed.push_back(t);
    }
    if (dropped) *dropped = lost;
    return ReprojectionLikelihood(camera_, M_, offset_, z_B_, std::move(fixed), std::sqrt(outlier2_));
  }
  // The likelihood raised to the power f (every term's weight scaled by f): f < 1 flattens
  // it, so that near-equal hypotheses of a global search are not decided by a pixel of
  // noise before the walk shows which one is right.
  ReprojectionLikelihood tempered(double f) const {
    ReprojectionLikelihood t = *this;
    for (ReprojectionTerm& x : t.terms_) x.inv_var *= f;
    return t;
  }
  // True when some term still needs a per-particle association.
  bool has_reused() const {
    for (const ReprojectionTerm& t : terms_)
      if (t.klass >= 0) return true;
    return false;
  }

  // log p(observations | body at (x, y, z_B), yaw offset e), up to a constant. The true
  // attitude is Rz(e) R_BtoW (the particle's yaw offset of the AHRS, heading_noise.hpp), so
  // a world offset reaches the camera as M Rz(-e) (p_L - p_B).
  double operator()(double x, double y, double e = 0.0) const {
    const double c = std::cos(e), s = std::sin(e);
    double ll = 0.0;
    for (std::size_t i = 0; i < terms_.size(); ++i) {
      const ReprojectionTerm& t = terms_[i];
      const Eigen::Vector3d* p_L = led_for(i, x, y, c, s);
      if (!p_L) {  // no copy of the class where this particle looks: as an outlier
        ll -= 0.5 * outlier2_ * t.inv_var * 2.0;
        continue;
      }
      const Eigen::Vector3d d = *p_L - Eigen::Vector3d(x, y, z_B_);
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
    for (std::size_t i = 0; i < terms_.size(); ++i) {
      const ReprojectionTerm& t = terms_[i];
      Eigen::Vector2d uv;
      const Eigen::Vector3d* p_L = led_for(i, x, y, ce, se);
      if (!p_L) return 1e9;
      const Eigen::Vector3d d = *p_L - Eigen::Vector3d(x, y, z_B_);
      if (!camera_.project(M_ * Eigen::Vector3d(ce * d.x() + se * d.y(), -se * d.x() + ce * d.y(), d.z()) - offset_, uv))
        return 1e9;
      s += (uv - t.uv).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(s / n) : 0.0;
  }
  std::size_t size() const { return terms_.size(); }
  // Beyond this pixel error a blob counts as an outlier (the flattened tail).
  double outlier_px() const { return std::sqrt(outlier2_); }

  // Inverse of the model for initialisation: the body (x, y) that puts term i's LED exactly
  // on its observed pixel (the bearing ray meets the LED's height above z_B). nullopt when
  // the ray does not point up towards the LED plane.
  std::optional<Eigen::Vector2d> invert(std::size_t i) const {
    const ReprojectionTerm& t = terms_[i];
    if (t.klass >= 0) return std::nullopt;  // which copy: resolved() first
    const Eigen::Vector3d ray_inW = M_.transpose() * camera_.bearing(t.uv);  // camera -> world
    const Eigen::Vector3d p_CinW_rel = M_.transpose() * offset_;              // camera lever arm, world
    const double dz = t.p_LinW.z() - (z_B_ + p_CinW_rel.z());
    if (ray_inW.z() < 0.05 || dz <= 0.0) return std::nullopt;
    const Eigen::Vector3d p_CinW = t.p_LinW - ray_inW * (dz / ray_inW.z());
    return Eigen::Vector2d(p_CinW.x() - p_CinW_rel.x(), p_CinW.y() - p_CinW_rel.y());
  }

 private:
  ReprojectionLikelihood(const CameraModel& camera, const Eigen::Matrix3d& M, const Eigen::Vector3d& offset, double z_B,
                         std::vector<ReprojectionTerm> terms, double outlier_px)
      : camera_(camera), terms_(std::move(terms)), M_(M), offset_(offset), z_B_(z_B), outlier2_(outlier_px * outlier_px) {}

  int copy_for(std::size_t i, double x, double y, double c, double s) const {
    const Eigen::Vector2d& w = ceiling_[i];
    if (!std::isfinite(w.x())) return -1;
    const int klass = terms_[i].klass;
    return reuse_.index->nearest(klass, x + c * w.x() - s * w.y(), y + s * w.x() + c * w.y(),
                                 reuse_.index->capture_radius(klass));
  }

  const CameraModel& camera_;
  std::vector<ReprojectionTerm> terms_;
  Eigen::Matrix3d M_;
  Eigen::Vector3d offset_;
  double z_B_;
  double outlier2_;
  ReuseAssociation reuse_;
  std::vector<Eigen::Vector2d> ceiling_;  // per term: w of the association (NaN: none)
};

}  // namespace luxloc
