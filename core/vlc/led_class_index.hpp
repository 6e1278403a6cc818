#pragma once
// Spatial index of an LED map by frequency class (issue 14): "which copy of frequency
// class k is nearest to this point on the ceiling?" in constant time, whatever the map's
// size. Each reused class has a uniform grid over the map's floor-plane bounds with cells
// of half the class's own reuse distance, so the nearest copy within half that distance
// lies in the 3x3 cells around the query; a class of one LED answers without a grid.
// Also: every LED within a radius (calib ledmap check, the simulator's renderer).
//
// Memory: one int per LED plus one per cell (cells at least 0.5 m), and the capture rasters
// (one int per raster cell plus ~20 per LED): a 5000-LED map over 200 m x 100 m with 12
// classes stays under a few MB.
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "core/vlc/led_map.hpp"

namespace luxloc {

class LedClassIndex {
 public:
  LedClassIndex() = default;
  explicit LedClassIndex(const LedMap& map);

  // The member of class `klass` nearest (x, y) in the floor plane within max_dist_m
  // (index into the map's leds()), -1 when none is that close.
  int nearest(int klass, double x, double y, double max_dist_m) const;
  // Every LED within r of (x, y) in the floor plane (appended to out, any order).
  void within(double x, double y, double r, std::vector<int>& out) const;
  // Half the class's own smallest reuse distance (inf for a class of one): the gate
  // within which the nearest copy is the only plausible one.
  double capture_radius(int klass) const { return classes_[static_cast<std::size_t>(klass)].capture_m; }
  std::size_t memory_bytes() const;
  // nearest(klass, x, y, capture_radius(klass)) inline: the per-particle association's call
  // (one raster cell, no function call when the class has a raster).
  int nearest_captured(int klass, double x, double y) const {
    if (klass < 0 || static_cast<std::size_t>(klass) >= classes_.size()) return -1;
    const ClassGrid& cg = classes_[static_cast<std::size_t>(klass)];
    const Raster& r = cg.raster;
    if (cg.single >= 0 || r.nx == 0) return nearest(klass, x, y, cg.capture_m);
    const double fi = std::floor((x - r.x0) * r.inv_cell), fj = std::floor((y - r.y0) * r.inv_cell);
    if (!(fi >= 0.0 && fj >= 0.0 && fi < r.nx && fj < r.ny)) return -1;  // also NaN
    const std::size_t c = static_cast<std::size_t>(fj) * static_cast<std::size_t>(r.nx) + static_cast<std::size_t>(fi);
    int best = -1;
    double best2 = cg.capture_m * cg.capture_m;
    for (int k = r.start[c]; k < r.start[c + 1]; ++k) {
      const int i = r.items[static_cast<std::size_t>(k)];
      const Eigen::Vector2d& p = xy_[static_cast<std::size_t>(i)];
      const double d2 = (p.x() - x) * (p.x() - x) + (p.y() - y) * (p.y() - y);
      if (d2 <= best2) {
        best2 = d2;
        best = i;
      }
    }
    return best;
  }

 private:
  struct Grid {  // CSR: items of cell c are items[start[c] .. start[c+1])
    double x0 = 0, y0 = 0, cell = 1;
    int nx = 0, ny = 0;
    std::vector<int> start, items;
    template <typename F>
    void visit(double x, double y, double r, F&& f) const;
  };
  // Capture raster (the per-particle association's fast path, queries within the capture
  // radius): cells of half the capture radius, each listing the copies whose
  // capture disc touches it (one, two or three near the boundaries between discs), so the
  // copy within the capture radius of a point is among the few of the point's own cell:
  // one cell lookup instead of a 3 x 3 search.
  struct Raster {
    double x0 = 0, y0 = 0, inv_cell = 1;
    int nx = 0, ny = 0;
    std::vector<int> start, items;  // CSR as Grid
  };
  struct ClassGrid {
    int single = -1;  // the member of a class of one
    double capture_m = 0.0;
    Grid grid;
    Raster raster;  // empty (nx == 0) when it would be too large: the grid answers
  };
  static Raster make_raster(const std::vector<Eigen::Vector2d>& pts, const std::vector<int>& ids, double capture);
  static Grid make_grid(const std::vector<Eigen::Vector2d>& pts, const std::vector<int>& ids, const Eigen::Vector4d& b,
                        double cell);

  std::vector<Eigen::Vector2d> xy_;  // per LED
  std::vector<ClassGrid> classes_;
  Grid all_;
};

}  // namespace luxloc
