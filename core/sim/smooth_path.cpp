#include "core/sim/smooth_path.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace luxloc::sim {
namespace {

// Standard normal CDF of x / sigma, kernel K and its derivative K'.
double Phi(double x, double sigma) { return 0.5 * std::erfc(-x / (sigma * std::numbers::sqrt2)); }
double K(double x, double sigma) {
  return std::exp(-0.5 * x * x / (sigma * sigma)) / (sigma * std::sqrt(2.0 * std::numbers::pi));
}
double dK(double x, double sigma) { return -x / (sigma * sigma) * K(x, sigma); }

}  // namespace

SmoothPath::SmoothPath(std::vector<Eigen::Vector2d> waypoints, double sigma_m)
    : pts_(std::move(waypoints)), sigma_(sigma_m) {
  if (pts_.size() < 3) throw std::invalid_argument("SmoothPath: needs at least 3 waypoints");
  if (!(sigma_ > 0.0)) throw std::invalid_argument("SmoothPath: sigma must be > 0");
  const std::size_t n = pts_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d d = pts_[(k + 1) % n] - pts_[k];
    const double len = d.norm();
    if (!(len > 1e-9)) throw std::invalid_argument("SmoothPath: repeated waypoint");
    start_.push_back(length_);
    seg_len_.push_back(len);
    dir_.push_back(d / len);
    length_ += len;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (dir_[k].dot(dir_[(k + 1) % n]) < -0.9)
      throw std::invalid_argument("SmoothPath: U-turn at a waypoint (turn > ~155 deg)");
  // Only the copies of the polygon one period either side are summed (see at()).
  if (length_ < 8.0 * sigma_) throw std::invalid_argument("SmoothPath: polygon shorter than 8 sigma");
}

Eigen::Vector2d SmoothPath::polygon_at(double u) const {
  double s = std::fmod(u, length_);
  if (s < 0) s += length_;
  for (std::size_t k = 0; k < pts_.size(); ++k)
    if (s < start_[k] + seg_len_[k] || k + 1 == pts_.size()) return pts_[k] + dir_[k] * (s - start_[k]);
  return pts_.front();
}

// c(u) = integral of polygon(s) K(u - s) ds. On segment k, polygon(s) = P_k + d_k (s - a)
// for s in [a, b]; with tau = u - s:
//   M0 = int_{u-b}^{u-a} K = Phi(u-a) - Phi(u-b),  M1 = int tau K = sigma^2 (K(u-b) - K(u-a)),
//   contribution = P_k M0 + d_k ((u - a) M0 - M1),
// and the derivatives follow: c' = sum d_k M0, c'' = sum d_k (K(u-a) - K(u-b)), c''' with K'.
PathPoint SmoothPath::at(double u) const {
  double s = std::fmod(u, length_);
  if (s < 0) s += length_;
  PathPoint p;
  for (int wrap = -1; wrap <= 1; ++wrap) {
    for (std::size_t k = 0; k < pts_.size(); ++k) {
      const double a = start_[k] + wrap * length_;
      const double b = a + seg_len_[k];
      const double M0 = Phi(s - a, sigma_) - Phi(s - b, sigma_);
      const double Ka = K(s - a, sigma_), Kb = K(s - b, sigma_);
      const double M1 = sigma_ * sigma_ * (Kb - Ka);
      p.c += pts_[k] * M0 + dir_[k] * ((s - a) * M0 - M1);
      p.c1 += dir_[k] * M0;
      p.c2 += dir_[k] * (Ka - Kb);
      p.c3 += dir_[k] * (dK(s - a, sigma_) - dK(s - b, sigma_));
    }
  }
  return p;
}

}  // namespace luxloc::sim
