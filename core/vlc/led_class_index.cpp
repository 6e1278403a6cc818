#include "core/vlc/led_class_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace luxloc {

namespace {
// Cells a grid or a class's capture raster may hold at most: 4M (16 MB of int offsets).
constexpr double kMaxCells = 4.0 * 1024 * 1024;
}  // namespace

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
  // At most kMaxCells: over a huge extent the cells grow instead (a query visits more LEDs
  // per cell, never a wrong one).
  while (((b[2] - b[0]) / cell + 3.0) * ((b[3] - b[1]) / cell + 3.0) > kMaxCells) cell *= 2.0;
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

LedClassIndex::Raster LedClassIndex::make_raster(const std::vector<Eigen::Vector2d>& pts, const std::vector<int>& ids,
                                                 double capture) {
  Raster r;
  if (ids.empty() || !(capture > 0.0) || !std::isfinite(capture)) return r;
  const double cell = 0.5 * capture;
  double x_lo = std::numeric_limits<double>::infinity(), y_lo = x_lo, x_hi = -x_lo, y_hi = -x_lo;
  for (int id : ids) {
    const Eigen::Vector2d& p = pts[static_cast<std::size_t>(id)];
    x_lo = std::min(x_lo, p.x());
    x_hi = std::max(x_hi, p.x());
    y_lo = std::min(y_lo, p.y());
    y_hi = std::max(y_hi, p.y());
  }
  // The discs' extent plus a cell: a query outside it has no copy within the capture radius.
  r.x0 = x_lo - capture - cell;
  r.y0 = y_lo - capture - cell;
  const double nxd = std::floor((x_hi + capture + cell - r.x0) / cell) + 1.0;
  const double nyd = std::floor((y_hi + capture + cell - r.y0) / cell) + 1.0;
  // At most kMaxCells per class: beyond that (a tiny reuse distance over a huge floor) the
  // grid search answers instead.
  if (!(nxd * nyd <= kMaxCells)) return Raster{};
  r.nx = static_cast<int>(nxd);
  r.ny = static_cast<int>(nyd);
  r.inv_cell = 1.0 / cell;
  const auto cells = static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny);
  r.start.assign(cells + 1, 0);
  const double c2 = capture * capture;
  // Every cell whose rectangle comes within the capture radius of the copy (closed disc).
  const auto for_cells = [&](const Eigen::Vector2d& p, auto&& f) {
    const int i0 = std::max(0, static_cast<int>(std::floor((p.x() - capture - r.x0) * r.inv_cell)));
    const int i1 = std::min(r.nx - 1, static_cast<int>(std::floor((p.x() + capture - r.x0) * r.inv_cell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((p.y() - capture - r.y0) * r.inv_cell)));
    const int j1 = std::min(r.ny - 1, static_cast<int>(std::floor((p.y() + capture - r.y0) * r.inv_cell)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double cx0 = r.x0 + i * cell, cy0 = r.y0 + j * cell;
        const double dx = std::max({cx0 - p.x(), 0.0, p.x() - (cx0 + cell)});
        const double dy = std::max({cy0 - p.y(), 0.0, p.y() - (cy0 + cell)});
        // A hair of slack: a query's own cell index comes from the same rounding.
        if (dx * dx + dy * dy <= c2 * (1.0 + 1e-9) + 1e-12) f(static_cast<std::size_t>(j) * static_cast<std::size_t>(r.nx) + static_cast<std::size_t>(i));
      }
  };
  for (int id : ids) for_cells(pts[static_cast<std::size_t>(id)], [&](std::size_t c) { ++r.start[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) r.start[c + 1] += r.start[c];
  r.items.resize(static_cast<std::size_t>(r.start[cells]));
  std::vector<int> fill(r.start.begin(), r.start.end() - 1);
  for (int id : ids)
    for_cells(pts[static_cast<std::size_t>(id)], [&](std::size_t c) { r.items[static_cast<std::size_t>(fill[c]++)] = id; });
  return r;
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
    cg.raster = make_raster(xy_, m, cg.capture_m);
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
  if (cg.single >= 0) {
    consider(cg.single);
  } else if (cg.raster.nx > 0 && max_dist_m <= cg.capture_m) {
    // Every copy within the capture radius of (x, y) is listed in (x, y)'s raster cell.
    const Raster& r = cg.raster;
    const double fi = std::floor((x - r.x0) * r.inv_cell), fj = std::floor((y - r.y0) * r.inv_cell);
    if (!(fi >= 0.0 && fj >= 0.0 && fi < r.nx && fj < r.ny)) return -1;  // also NaN
    const std::size_t c = static_cast<std::size_t>(fj) * static_cast<std::size_t>(r.nx) + static_cast<std::size_t>(fi);
    for (int k = r.start[c]; k < r.start[c + 1]; ++k) consider(r.items[static_cast<std::size_t>(k)]);
  } else {
    cg.grid.visit(x, y, max_dist_m, consider);
  }
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
  for (const ClassGrid& c : classes_)
    n += sizeof(ClassGrid) + (c.grid.start.size() + c.grid.items.size() + c.raster.start.size() + c.raster.items.size()) * sizeof(int);
  return n;
}

}  // namespace luxloc
