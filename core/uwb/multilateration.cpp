#include "core/uwb/multilateration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace luxloc {
namespace {

// Horizontal range of each measurement, for the linear start.
double horizontal(const RangeToAnchor& r, double z_B) {
  const double dz = z_B - r.p_AinW.z();
  return std::sqrt(std::max(0.0, r.range_m * r.range_m - dz * dz));
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// The convex hull of pts, counter-clockwise (Andrew's monotone chain).
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

// Distance of p outside a convex_hull() (0 inside; for a hull of fewer than 3 points, the
// distance to the nearest segment).
double outside_hull_m(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  bool inside = hull.size() >= 3;
  double best = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    if (hull.size() >= 3 && cross(a, b, p) < 0) inside = false;  // counter-clockwise hull
    const Eigen::Vector2d ab = b - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return inside ? 0.0 : best;
}

std::optional<Multilateration> solve(const std::vector<RangeToAnchor>& ranges, double z_B,
                                     const MultilaterationOptions& o,
                                     const std::optional<Eigen::Vector2d>& start = std::nullopt) {
  const std::size_t n = ranges.size();
  if (n < 3) return std::nullopt;
  for (const RangeToAnchor& r : ranges)
    if (!r.p_AinW.allFinite() || !std::isfinite(r.range_m) || r.range_m < 0.0) return std::nullopt;

  // Linear start: (x - xi)^2 + (y - yi)^2 = ri^2 minus the same for anchor 0.
  Eigen::MatrixXd A(n - 1, 2);
  Eigen::VectorXd b(n - 1);
  const Eigen::Vector2d a0 = ranges[0].p_AinW.head<2>();
  const double r0 = horizontal(ranges[0], z_B);
  for (std::size_t i = 1; i < n; ++i) {
    const Eigen::Vector2d ai = ranges[i].p_AinW.head<2>();
    const double ri = horizontal(ranges[i], z_B);
    A.row(static_cast<Eigen::Index>(i - 1)) = 2.0 * (ai - a0).transpose();
    b(static_cast<Eigen::Index>(i - 1)) = r0 * r0 - ri * ri + ai.squaredNorm() - a0.squaredNorm();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (sv.size() < 2 || !(sv(1) > 1e-6 * std::max(1.0, sv(0)))) return std::nullopt;  // collinear anchors
  Eigen::Vector2d p = start ? *start : Eigen::Vector2d(svd.solve(b));

  Multilateration out;
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
  Eigen::VectorXd e(n), w = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(n));
  for (int it = 0; it < o.max_iterations; ++it) {
    Eigen::MatrixXd J(n, 2);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d(p.x(), p.y(), z_B) - ranges[i].p_AinW;
      const double dn = std::max(d.norm(), 1e-6);
      const auto k = static_cast<Eigen::Index>(i);
      e(k) = dn - ranges[i].range_m;
      J.row(k) = d.head<2>().transpose() / dn;
      const double z = std::abs(e(k)) / o.range_sigma_m;
      w(k) = o.huber_k > 0.0 && z > o.huber_k ? o.huber_k / z : 1.0;
    }
    H = J.transpose() * w.asDiagonal() * J;
    const Eigen::Vector2d g = J.transpose() * w.asDiagonal() * e;
    const Eigen::Vector2d step = H.ldlt().solve(-g);
    if (!step.allFinite()) return std::nullopt;
    p += step;
    out.iterations = it + 1;
    if (step.norm() < 1e-6) break;
  }
  double s2 = 0.0, sw = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    s2 += w(k) * e(k) * e(k);
    sw += w(k);
  }
  out.rms_m = std::sqrt(s2 / std::max(sw, 1e-9));
  if (!p.allFinite() || !(out.rms_m <= o.max_rms_m) || !(H.determinant() > 1e-12)) return std::nullopt;
  out.fix.z = p;
  out.fix.R = o.range_sigma_m * o.range_sigma_m * H.inverse();
  return out;
}

}  // namespace

std::optional<Multilateration> multilaterate(const std::vector<RangeToAnchor>& ranges, double z_B,
                                             const MultilaterationOptions& o, const std::vector<Eigen::Vector2d>& area) {
  std::vector<Eigen::Vector2d> hull_points = area;
  if (hull_points.empty())
    for (const RangeToAnchor& r : ranges) hull_points.push_back(r.p_AinW.head<2>());
  const std::vector<Eigen::Vector2d> hull = convex_hull(hull_points);
  std::optional<Multilateration> best = solve(ranges, z_B, o);
  // NLOS identification: with a redundant anchor, a residual well above the noise
  // suggests one biased range; the subset without it that fits best wins if it fits
  // clearly better.
  if (ranges.size() >= 4 && o.huber_k > 0.0 && (!best || best->rms_m > 2.5 * o.range_sigma_m)) {
    for (std::size_t skip = 0; skip < ranges.size(); ++skip) {
      std::vector<RangeToAnchor> subset;
      for (std::size_t i = 0; i < ranges.size(); ++i)
        if (i != skip) subset.push_back(ranges[i]);
      const std::optional<Multilateration> m = solve(subset, z_B, o);
      if (m && (!best || m->rms_m < 0.5 * best->rms_m)) best = m;
    }
  }
  if (best && outside_hull_m(hull, best->fix.z) > o.hull_margin_m) {
    // A mirror? Re-solve from inside the hull: the centroid, and the solution reflected
    // through it; an inside fit at most 1.5x the residual RMS (or within one range sigma)
    // is the answer, else the outside one stands, flagged.
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& a : hull_points) c += a / static_cast<double>(hull_points.size());
    bool outside = true;
    for (const Eigen::Vector2d& s : {c, Eigen::Vector2d(2.0 * c - best->fix.z)}) {
      const std::optional<Multilateration> m = solve(ranges, z_B, o, s);
      if (m && outside_hull_m(hull, m->fix.z) <= o.hull_margin_m &&
          m->rms_m <= std::max(1.5 * best->rms_m, best->rms_m + o.range_sigma_m)) {
        best = m;
        outside = false;
        break;
      }
    }
    best->outside_hull = outside;
  }
  return best;
}

}  // namespace luxloc
