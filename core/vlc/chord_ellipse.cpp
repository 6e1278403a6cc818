#include "core/vlc/chord_ellipse.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace luxloc {

ChordEllipse ChordEllipse::fit(const std::vector<Eigen::Vector2d>& pts) {
  ChordEllipse el;
  if (pts.size() < 6) return el;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  double s = 0;
  for (const auto& p : pts) s = std::max(s, (p - mean).cwiseAbs().maxCoeff());
  if (!(s > 0.5)) return el;
  el.u0_ = mean.x();
  el.v0_ = mean.y();
  el.s_ = s;
  // Normalised coordinates keep the 5x5 normal equations well conditioned.
  Eigen::Matrix<double, 5, 5> ata = Eigen::Matrix<double, 5, 5>::Zero();
  Eigen::Matrix<double, 5, 1> atb = Eigen::Matrix<double, 5, 1>::Zero();
  for (const auto& p : pts) {
    const double x = (p.x() - el.u0_) / s, y = (p.y() - el.v0_) / s;
    Eigen::Matrix<double, 5, 1> row;
    row << x * y, y * y, x, y, 1.0;
    ata.noalias() += row * row.transpose();
    atb.noalias() += row * (-x * x);
  }
  const Eigen::Matrix<double, 5, 1> th = ata.ldlt().solve(atb);
  if (!th.allFinite()) return el;
  el.b_ = th(0);
  el.e_ = th(1);
  el.a_ = th(2);
  el.d_ = th(3);
  el.g_ = th(4);
  if (!(4 * el.e_ - el.b_ * el.b_ > 1e-9)) return el;  // not an ellipse
  Eigen::Matrix2d m2;
  m2 << 2, el.b_, el.b_, 2 * el.e_;
  const Eigen::Vector2d c = m2.inverse() * Eigen::Vector2d(-el.a_, -el.d_);
  const double fc = c.x() * c.x() + el.b_ * c.x() * c.y() + el.e_ * c.y() * c.y() + el.a_ * c.x() + el.d_ * c.y() + el.g_;
  if (!(fc < 0)) return el;  // empty
  Eigen::Matrix2d M;
  M << 1, 0.5 * el.b_, 0.5 * el.b_, el.e_;
  const Eigen::Matrix2d Mi = M.inverse();
  el.centre_ = {el.u0_ + s * c.x(), el.v0_ + s * c.y()};
  el.radius_ = s * std::sqrt(-fc / std::sqrt(M.determinant()));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(M);
  el.axis_ratio_ = std::sqrt(std::max(0.0, eig.eigenvalues()(0)) / std::max(eig.eigenvalues()(1), 1e-300));
  const double half_v = s * std::sqrt(-fc * Mi(1, 1));
  el.half_u_ = s * std::sqrt(-fc * Mi(0, 0));
  el.v_top_ = el.centre_.y() - half_v;
  el.v_bot_ = el.centre_.y() + half_v;
  el.ok_ = std::isfinite(el.radius_) && el.radius_ > 0.5;
  for (int i = -8; i <= 8 && el.ok_; ++i) {
    double mid = 0, hw = 0;
    el.chord(el.centre_.y() + half_v * i / 9.0, mid, hw);
    el.max_half_width_ = std::max(el.max_half_width_, hw);
  }
  return el;
}

bool ChordEllipse::chord(double v, double& mid, double& half_width) const {
  const double y = (v - v0_) / s_;
  const double p = b_ * y + a_, q = e_ * y * y + d_ * y + g_;
  const double disc = p * p - 4 * q;
  mid = u0_ + s_ * (-0.5 * p);
  half_width = disc > 0 ? 0.5 * s_ * std::sqrt(disc) : 0.0;
  return disc > 0;
}

double ChordEllipse::rms_residual(const std::vector<Eigen::Vector2d>& pts) const {
  if (pts.empty()) return 0.0;
  double ss = 0;
  for (const auto& p : pts) {
    double mid, hw;
    const double r = chord(p.y(), mid, hw) ? std::abs(std::abs(p.x() - mid) - hw) : radius_;
    ss += r * r;
  }
  return std::sqrt(ss / static_cast<double>(pts.size()));
}

int ChordEllipse::arc_sectors(const std::vector<Eigen::Vector2d>& pts) const {
  // Conic matrix M = [1 b/2; b/2 e] = L L^T (Cholesky); q = L^T d maps the ellipse to a circle.
  const double l10 = 0.5 * b_, l11sq = e_ - l10 * l10;
  if (!(l11sq > 0)) return 0;
  const double l11 = std::sqrt(l11sq);
  unsigned mask = 0;
  for (const auto& p : pts) {
    const double x = (p.x() - centre_.x()) / s_, y = (p.y() - centre_.y()) / s_;
    const double ang = std::atan2(l11 * y, x + l10 * y) + std::numbers::pi;
    mask |= 1u << std::min(11, static_cast<int>(ang / (std::numbers::pi / 6)));
  }
  return std::popcount(mask);
}

}  // namespace luxloc
