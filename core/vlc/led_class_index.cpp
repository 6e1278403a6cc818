#include "core/vlc/led_class_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace luxloc {

template <typename F>
void LedClassIndex::Grid::visit(double x, double y, double r, F&& f) const {
  if (nx == 0 || !std::isfinite(x) || !std::isfinite(y) || !(r >= 0.0)) return;
  // Clamped in double before the cast: a query far off the map must not overflow an int.
  const auto cell_at = [this](double v, double origin, int n) {
    return static_cast<int>(std::clamp(std::floor((v - origin) / cell), -1.0, static_cast<double>(n)));
  };
  const int i0 = std::max(0, cell_at(x - r, x0, nx)), i1 = std::min(nx - 1, cell_at(x + r, x0, nx));
  const int j0 = std::max(0, cell_at(y - r, y0, ny)), j1 = std::min(ny - 1, cell_at(y + r, y0, ny));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const int c = j * nx + i;
      for (int k = start[static_cast<std::size_t>(c)]; k < start[static_cast<std::size_t>(c) + 1]; ++k)
        f(items[static_cast<std::size_t>(k)]);
    }
}

LedClassIndex::Grid LedClassIndex::make_grid(const std::vector<Eigen::Vector2d>& pts, const std::vector<int>& ids,
                                             const Eigen::Vector4d& b, double cell) {
  Grid g;
  g.cell = cell;
  g.x0 = b[0] - cell;
  g.y0 = b[1] - cell;
  g.nx = static_cast<int>(std::floor((b[2] - g.x0) / cell)) + 2;
  g.ny = static_cast<int>(std::floor((b[3] - g.y0) / cell)) + 2;
  const auto cells = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  std::vector<int> cell_of(ids.size());
  g.start.assign(cells + 1, 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Eigen::Vector2d& p = pts[static_cast<std::size_t>(ids[k])];
    const int i = std::clamp(static_cast<int>(std::floor((p.x() - g.x0) / cell)), 0, g.nx - 1);
    const int j = std::clamp(static_cast<int>(std::floor((p.y() - g.y0) / cell)), 0, g.ny - 1);
    cell_of[k] = j * g.nx + i;
    ++g.start[static_cast<std::size_t>(cell_of[k]) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  g.items.resize(ids.size());
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t k = 0; k < ids.size(); ++k) g.items[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[k])]++)] = ids[k];
  return g;
}

LedClassIndex::LedClassIndex(const LedMap& map) {
  xy_.reserve(map.size());
  for (const Led& l : map.leds()) xy_.push_back(l.p_inW.head<2>());
  const Eigen::Vector4d b = map.bounds();
  std::vector<int> all(map.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  // 2 m cells for the all-LED grid: ceiling lights sit 1-3 m apart.
  if (!all.empty()) all_ = make_grid(xy_, all, b, 2.0);
  classes_.resize(map.classes().size());
  for (std::size_t k = 0; k < classes_.size(); ++k) {
    const std::vector<int>& m = map.classes()[k].members;
    ClassGrid& cg = classes_[k];
    if (m.size() == 1) {
      cg.single = m.front();
      cg.capture_m = std::numeric_limits<double>::infinity();
      continue;
    }
    double d_min = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < m.size(); ++a)
      for (std::size_t c = a + 1; c < m.size(); ++c)
        d_min = std::min(d_min, (xy_[static_cast<std::size_t>(m[a])] - xy_[static_cast<std::size_t>(m[c])]).norm());
    cg.capture_m = 0.5 * d_min;
    cg.grid = make_grid(xy_, m, b, std::max(0.5, cg.capture_m));
  }
}

int LedClassIndex::nearest(int klass, double x, double y, double max_dist_m) const {
  if (klass < 0 || static_cast<std::size_t>(klass) >= classes_.size()) return -1;
  const ClassGrid& cg = classes_[static_cast<std::size_t>(klass)];
  int best = -1;
  double best2 = max_dist_m * max_dist_m;
  const auto consider = [&](int i) {
    const Eigen::Vector2d& p = xy_[static_cast<std::size_t>(i)];
    const double d2 = (p.x() - x) * (p.x() - x) + (p.y() - y) * (p.y() - y);
    if (d2 <= best2) {
      best2 = d2;
      best = i;
    }
  };
  if (cg.single >= 0)
    consider(cg.single);
  else
    cg.grid.visit(x, y, max_dist_m, consider);
  return best;
}

void LedClassIndex::within(double x, double y, double r, std::vector<int>& out) const {
  const double r2 = r * r;
  all_.visit(x, y, r, [&](int i) {
    if ((xy_[static_cast<std::size_t>(i)] - Eigen::Vector2d(x, y)).squaredNorm() <= r2) out.push_back(i);
  });
}

std::size_t LedClassIndex::memory_bytes() const {
  std::size_t n = xy_.size() * sizeof(Eigen::Vector2d) + (all_.start.size() + all_.items.size()) * sizeof(int);
  for (const ClassGrid& c : classes_) n += sizeof(ClassGrid) + (c.grid.start.size() + c.grid.items.size()) * sizeof(int);
  return n;
}

}  // namespace luxloc
