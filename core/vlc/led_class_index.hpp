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
