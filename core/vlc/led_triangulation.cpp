#include "core/vlc/led_triangulation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace luxloc {
namespace {

double ray_distance(const BearingRay& r, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = p - r.origin_inW;
  return (v - r.dir_inW * r.dir_inW.dot(v)).norm();
}

}  // namespace

TriangulatedPoint triangulate(const std::vector<BearingRay>& rays, const TriangulationOptions& o) {
  TriangulatedPoint out;
  out.rays = rays.size();
  if (rays.size() < 2) return out;
  std::vector<double> w(rays.size(), 1.0);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int it = 0; it < std::max(1, o.iterations); ++it) {
    if (o.fixed_z) {
      // Each ray crosses the plane z = z0 at c_i; minimise sum w_i |X_xy - c_i|^2 weighted
      // by how steeply the ray meets the plane (a grazing ray's crossing is uncertain).
      Eigen::Vector2d num = Eigen::Vector2d::Zero();
      double den = 0.0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const BearingRay& r = rays[i];
        if (std::abs(r.dir_inW.z()) < 1e-3) continue;
        const double s = (*o.fixed_z - r.origin_inW.z()) / r.dir_inW.z();
        if (s <= 0) continue;
        const Eigen::Vector2d c = (r.origin_inW + s * r.dir_inW).head<2>();
        const double wi = w[i] * r.dir_inW.z() * r.dir_inW.z();
        num += wi * c;
        den += wi;
      }
      if (den <= 0) return out;
      p = Eigen::Vector3d(num.x() / den, num.y() / den, *o.fixed_z);
    } else {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      double wsum = 0.0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - rays[i].dir_inW * rays[i].dir_inW.transpose();
        A += w[i] * P;
        b += w[i] * P * rays[i].origin_inW;
        wsum += w[i];
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A / wsum);
      if (eig.eigenvalues().minCoeff() < o.min_conditioning) return out;
      p = A.ldlt().solve(b);
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double d = ray_distance(rays[i], p);
      w[i] = d <= o.huber_m ? 1.0 : o.huber_m / d;
    }
  }
  double ss = 0.0;
  for (const BearingRay& r : rays) ss += std::pow(ray_distance(r, p), 2);
  out.ok = p.allFinite();
  out.p_inW = p;
  out.rms_m = std::sqrt(ss / static_cast<double>(rays.size()));
  return out;
}

}  // namespace luxloc
