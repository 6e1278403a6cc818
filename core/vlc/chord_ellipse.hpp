#pragma once
// The envelope of an LED blob as an ellipse fitted to the left / right ends of its row
// chords. Horizontal chords of an ellipse have midpoints on a line and squared half-widths
// quadratic in the row, so the bright rows fix the ellipse even when dark stripes hide the
// rows between them, the camera is rolled (a rotated ellipse) or the border cuts the blob.
// Its centre is the blob centre that the stripes do not bias (SEEDS.md A, S203).
#include <Eigen/Core>
#include <vector>

namespace luxloc {

class ChordEllipse {
 public:
  // Algebraic least squares for u^2 + b uv + e v^2 + a u + d v + g = 0 over the edge points
  // (u = column, v = row). ok() is false for fewer than 6 points or a non-ellipse.
  static ChordEllipse fit(const std::vector<Eigen::Vector2d>& edge_points);

  bool ok() const { return ok_; }
  const Eigen::Vector2d& centre() const { return centre_; }
  double radius() const { return radius_; }          // sqrt(semi-axis product)
  double axis_ratio() const { return axis_ratio_; }  // minor / major
  double top() const { return v_top_; }              // first and last row covered
  double bottom() const { return v_bot_; }
  double half_width() const { return half_u_; }      // half the horizontal extent
  double max_chord_half_width() const { return max_half_width_; }

  // Chord of row v: midpoint and half-width; false when the row misses the ellipse.
  bool chord(double v, double& mid, double& half_width) const;
  // RMS horizontal distance of the points to the chord ends.
  double rms_residual(const std::vector<Eigen::Vector2d>& edge_points) const;
  // Occupied 30-degree sectors (of 12) of the boundary, angles taken on the ellipse mapped
  // to a circle: a short arc (a blob in an image corner) does not pin an ellipse down.
  int arc_sectors(const std::vector<Eigen::Vector2d>& edge_points) const;

 private:
  double b_ = 0, e_ = 0, a_ = 0, d_ = 0, g_ = 0;  // in coordinates (p - origin) / scale
  double u0_ = 0, v0_ = 0, s_ = 1;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double radius_ = 0, axis_ratio_ = 0, v_top_ = 0, v_bot_ = 0, half_u_ = 0, max_half_width_ = 0;
  bool ok_ = false;
};

}  // namespace luxloc
