#pragma once
// Tight coupling (issue: VLC): a particle at (x, y) predicts where each decoded LED should
// appear in the image; the log-likelihood is the robust (Huber-like, Cauchy tail) sum of
// squared pixel errors. One visible LED then still corrects the filter, where a loose fix
// needs the positioner to succeed first.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "core/filter/simd8.hpp"
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
    cache_camera();
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
    double c, s;
    turn(e, c, s);
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
      if (!project(p_LinC, uv)) {
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

  // operator() for n particles at (ox + x[k], oy + y[k]) with yaw offsets e[k] (e null: 0)
  // into out[k]: eight particles at a time in single precision, positions relative to
  // (ox, oy), the copy of a reused class from the class index's raster per lane.
  // ParticleFilter::weigh takes this path by itself. Agrees with operator() to float
  // rounding (a particle whose bearing point lies within ~1e-6 m of a capture boundary
  // may associate differently); offsets beyond 0.25 rad take operator() itself.
  void log_likelihood_block(double ox, double oy, const float* x, const float* y, const float* e, std::size_t n,
                            float* out) const {
    using simd8::F8;
    using simd8::I8;
    using simd8::splat;
    const float m00 = static_cast<float>(M_(0, 0)), m01 = static_cast<float>(M_(0, 1)), m02 = static_cast<float>(M_(0, 2));
    const float m10 = static_cast<float>(M_(1, 0)), m11 = static_cast<float>(M_(1, 1)), m12 = static_cast<float>(M_(1, 2));
    const float m20 = static_cast<float>(M_(2, 0)), m21 = static_cast<float>(M_(2, 1)), m22 = static_cast<float>(M_(2, 2));
    const float of0 = static_cast<float>(offset_.x()), of1 = static_cast<float>(offset_.y()),
                of2 = static_cast<float>(offset_.z());
    const float fx = static_cast<float>(fx_), fy = static_cast<float>(fy_), cx = static_cast<float>(cx_),
                cy = static_cast<float>(cy_);
    const float k1 = static_cast<float>(dist_[0]), k2 = static_cast<float>(dist_[1]), p1 = static_cast<float>(dist_[2]),
                p2 = static_cast<float>(dist_[3]), k3 = static_cast<float>(dist_[4]);
    const float o2 = static_cast<float>(outlier2_), inv_o2 = static_cast<float>(1.0 / outlier2_);
    const std::vector<Led>* leds = reuse_.map ? &reuse_.map->leds() : nullptr;
    for (std::size_t k0 = 0; k0 < n; k0 += 8) {
      const std::size_t len = std::min<std::size_t>(8, n - k0);
      alignas(32) float bx[8] = {}, by[8] = {}, be[8] = {};
      for (std::size_t l = 0; l < len; ++l) {
        bx[l] = x[k0 + l];
        by[l] = y[k0 + l];
        be[l] = e ? e[k0 + l] : 0.0f;
      }
      const F8 X = simd8::load(bx), Y = simd8::load(by), E = simd8::load(be);
      // Turn by the offset: Taylor to e^8 / e^7 (|e| < 0.25: < 1e-11).
      const F8 E2 = E * E;
      const F8 S = E * (1.0f + E2 * (-1.0f / 6 + E2 * (1.0f / 120 + E2 * (-1.0f / 5040))));
      const F8 Cs = 1.0f + E2 * (-0.5f + E2 * (1.0f / 24 + E2 * (-1.0f / 720 + E2 * (1.0f / 40320))));
      F8 ll{};
      for (std::size_t i = 0; i < terms_.size(); ++i) {
        const ReprojectionTerm& t = terms_[i];
        const float half_iv = static_cast<float>(0.5 * t.inv_var);
        F8 dx, dy, dz;
        I8 lost{};  // no copy of the class where the lane looks
        if (t.klass < 0) {
          dx = splat(static_cast<float>(t.p_LinW.x() - ox)) - X;
          dy = splat(static_cast<float>(t.p_LinW.y() - oy)) - Y;
          dz = splat(static_cast<float>(t.p_LinW.z() - z_B_));
        } else {
          const Eigen::Vector2d& w = ceiling_[i];
          if (!std::isfinite(w.x()) || !leds || !reuse_.index) {  // no association for any particle
            ll -= splat(half_iv * o2 * 2.0f);
            continue;
          }
          const float wx = static_cast<float>(w.x()), wy = static_cast<float>(w.y());
          alignas(32) float qx[8], qy[8], lx[8], ly[8], lz[8];
          alignas(32) std::int32_t lo[8];
          simd8::store(qx, X + Cs * wx - S * wy);
          simd8::store(qy, Y + S * wx + Cs * wy);
          for (int l = 0; l < 8; ++l) {
            const int k = reuse_.index->nearest_captured(t.klass, ox + static_cast<double>(qx[l]), oy + static_cast<double>(qy[l]));
            if (k < 0) {
              lo[l] = -1;
              lx[l] = ly[l] = 0.0f;
              lz[l] = 1.0f;
              continue;
            }
            const Eigen::Vector3d& p = (*leds)[static_cast<std::size_t>(k)].p_inW;
            lo[l] = 0;
            lx[l] = static_cast<float>(p.x() - ox);
            ly[l] = static_cast<float>(p.y() - oy);
            lz[l] = static_cast<float>(p.z() - z_B_);
          }
          std::memcpy(&lost, lo, sizeof lost);
          dx = simd8::load(lx) - X;
          dy = simd8::load(ly) - Y;
          dz = simd8::load(lz);
        }
        // World offset -> camera frame: M Rz(-e) d - offset.
        const F8 rx = Cs * dx + S * dy, ry = Cs * dy - S * dx;
        const F8 pcx = m00 * rx + m01 * ry + m02 * dz - of0;
        const F8 pcy = m10 * rx + m11 * ry + m12 * dz - of1;
        const F8 pcz = m20 * rx + m21 * ry + m22 * dz - of2;
        const I8 front = pcz > 1e-9f;
        const F8 iz = 1.0f / (front ? pcz : splat(1.0f));
        F8 xn = pcx * iz, yn = pcy * iz;
        if (distorted_) {
          const F8 r2 = xn * xn + yn * yn;
          const F8 radial = 1.0f + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
          const F8 xd = xn * radial + 2.0f * p1 * xn * yn + p2 * (r2 + 2.0f * xn * xn);
          const F8 yd = yn * radial + p1 * (r2 + 2.0f * yn * yn) + 2.0f * p2 * xn * yn;
          xn = xd;
          yn = yd;
        }
        const F8 du = fx * xn + cx - static_cast<float>(t.uv.x());
        const F8 dv = fy * yn + cy - static_cast<float>(t.uv.y());
        const F8 e2 = du * du + dv * dv;
        const F8 ratio = e2 * inv_o2;
        const F8 tail = o2 * (1.0f + simd8::log_positive(ratio > 1.0f ? ratio : splat(1.0f)));
        F8 loss = e2 < o2 ? e2 : tail;
        loss = e2 == e2 ? loss : e2;  // NaN stays NaN (the weighing refuses it)
        F8 contrib = front ? half_iv * loss : splat(half_iv * o2);
        contrib = lost != 0 ? splat(half_iv * o2 * 2.0f) : contrib;
        ll -= contrib;
      }
      alignas(32) float res[8];
      simd8::store(res, ll);
      for (std::size_t l = 0; l < len; ++l) {
        // Beyond the polynomial's range: the double path.
        out[k0 + l] = std::abs(be[l]) < 0.25f ? res[l]
                                               : static_cast<float>((*this)(ox + static_cast<double>(bx[l]),
                                                                            oy + static_cast<double>(by[l]),
                                                                            static_cast<double>(be[l])));
      }
    }
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
      : camera_(camera), terms_(std::move(terms)), M_(M), offset_(offset), z_B_(z_B), outlier2_(outlier_px * outlier_px) {
    cache_camera();
  }

  // The per-particle hot path (issue 14's bench: sincos, the out-of-line projection and a
  // 3 x 3 grid search were most of a particle's weighing): the camera's intrinsics cached,
  // the projection inlined (the same arithmetic as CameraModel::project, so the same
  // pixels), and the yaw offset's turn by a polynomial where offsets live.
  void cache_camera() {
    fx_ = camera_.fx;
    fy_ = camera_.fy;
    cx_ = camera_.cx;
    cy_ = camera_.cy;
    for (int k = 0; k < 5; ++k) dist_[k] = camera_.dist[static_cast<std::size_t>(k)];
    distorted_ = camera_.has_distortion();
  }
  bool project(const Eigen::Vector3d& p_inC, Eigen::Vector2d& uv) const {
    if (p_inC.z() <= 1e-9) return false;
    double x = p_inC.x() / p_inC.z(), y = p_inC.y() / p_inC.z();
    if (distorted_) {
      const double* d = dist_;
      const double r2 = x * x + y * y;
      const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
      const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
      const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
      x = xd;
      y = yd;
    }
    uv = {fx_ * x + cx_, fy_ * y + cy_};
    return true;
  }
  // cos and sin of a yaw offset: Taylor series to e^12 / e^11 for |e| < 0.25 rad (the
  // offsets the heading feedback keeps; truncation < 3e-18, below double rounding), libm
  // beyond.
  static void turn(double e, double& c, double& s) {
    if (std::abs(e) < 0.25) {
      const double e2 = e * e;
      s = e * (1.0 + e2 * (-1.0 / 6 + e2 * (1.0 / 120 + e2 * (-1.0 / 5040 + e2 * (1.0 / 362880 + e2 * (-1.0 / 39916800))))));
      c = 1.0 + e2 * (-0.5 + e2 * (1.0 / 24 + e2 * (-1.0 / 720 + e2 * (1.0 / 40320 + e2 * (-1.0 / 3628800 + e2 * (1.0 / 479001600))))));
    } else {
      c = std::cos(e);
      s = std::sin(e);
    }
  }

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
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0, dist_[5] = {};
  bool distorted_ = false;
};

}  // namespace luxloc
