#pragma once
// A closed walking path: a polygon through waypoints, convolved with a Gaussian of width
// sigma along its arc length. The corners become rounded turns of radius ~sigma and the
// curve is infinitely differentiable, with every derivative in closed form (erf / exp), so
// the IMU synthesised along it is exactly consistent (docs/SIMULATOR.md "Trajectory").
// The parameter u is the arc length of the polygon; |dc/du| = 1 on straights and drops to
// cos(turn/2) in the middle of a turn, which makes a walker slow down in corners.
#include <Eigen/Core>
#include <vector>

namespace luxloc::sim {

struct PathPoint {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();   // position (world x, y)
  Eigen::Vector2d c1 = Eigen::Vector2d::Zero();  // dc/du
  Eigen::Vector2d c2 = Eigen::Vector2d::Zero();  // d2c/du2
  Eigen::Vector2d c3 = Eigen::Vector2d::Zero();  // d3c/du3
};

class SmoothPath {
 public:
  // `waypoints`: the closed polygon's corners (the last joins the first); >= 3 points,
  // consecutive points distinct, no U-turn. Throws std::invalid_argument otherwise, or when
  // the polygon is shorter than 8 sigma.
  SmoothPath(std::vector<Eigen::Vector2d> waypoints, double sigma_m);

  PathPoint at(double u) const;  // any real u; periodic with period length()
  double length() const { return length_; }
  double sigma() const { return sigma_; }
  const std::vector<Eigen::Vector2d>& waypoints() const { return pts_; }
  // Polygon point at arc length u (unsmoothed), for tests and for placing start points.
  Eigen::Vector2d polygon_at(double u) const;

 private:
  std::vector<Eigen::Vector2d> pts_;
  std::vector<Eigen::Vector2d> dir_;  // unit direction of segment k (pts_[k] -> pts_[k+1])
  std::vector<double> start_;         // arc length at pts_[k]
  std::vector<double> seg_len_;
  double length_ = 0.0;
  double sigma_ = 0.5;
};

}  // namespace luxloc::sim
