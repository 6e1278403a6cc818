#include "core/vlc/frequency_plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "core/vlc/led_visibility.hpp"

namespace luxloc {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Every pair of positions closer than r, as per-position neighbour lists sorted by
// distance (a uniform grid of cell r: O(n) for a layout of bounded density).
struct Neighbours {
  std::vector<std::vector<std::pair<double, int>>> of;  // (distance, index)
};

Neighbours neighbours_within(const std::vector<Eigen::Vector2d>& p, double r) {
  Neighbours out;
  out.of.resize(p.size());
  if (p.empty() || !(r > 0.0)) return out;
  Eigen::Vector2d lo = p.front(), hi = p.front();
  for (const auto& q : p) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const int nx = static_cast<int>(std::floor((hi.x() - lo.x()) / r)) + 1;
  const int ny = static_cast<int>(std::floor((hi.y() - lo.y()) / r)) + 1;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  const auto cell_of = [&](const Eigen::Vector2d& q) {
    return std::pair<int, int>{std::min(nx - 1, static_cast<int>((q.x() - lo.x()) / r)),
                               std::min(ny - 1, static_cast<int>((q.y() - lo.y()) / r))};
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto [cx, cy] = cell_of(p[i]);
    cells[static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(cx)].push_back(
        static_cast<int>(i));
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto [cx, cy] = cell_of(p[i]);
    auto& list = out.of[i];
    for (int y = std::max(0, cy - 1); y <= std::min(ny - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(nx - 1, cx + 1); ++x)
        for (int j : cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(x)]) {
          if (j == static_cast<int>(i)) continue;
          const double d = (p[static_cast<std::size_t>(j)] - p[i]).norm();
          if (d < r) list.emplace_back(d, j);
        }
    std::sort(list.begin(), list.end());
  }
  return out;
}

// DSatur (Brelaz 1979): colour next the vertex with the most distinct neighbour colours
// (ties: most uncoloured neighbours, then a seeded random key), with its smallest free colour.
std::vector<int> dsatur(const std::vector<std::vector<int>>& adj, std::mt19937_64& rng, int& colours) {
  const std::size_t n = adj.size();
  std::vector<int> colour(n, -1), sat(n, 0), deg(n);
  std::vector<std::uint64_t> key(n);
  std::vector<std::vector<int>> seen(n);  // per vertex: count of neighbours of each colour
  std::set<std::tuple<int, int, std::uint64_t, int>> queue;
  for (std::size_t v = 0; v < n; ++v) {
    deg[v] = static_cast<int>(adj[v].size());
    key[v] = rng();
    queue.emplace(0, -deg[v], key[v], static_cast<int>(v));
  }
  colours = 0;
  while (!queue.empty()) {
    const int v = std::get<3>(*queue.begin());
    queue.erase(queue.begin());
    auto& s = seen[static_cast<std::size_t>(v)];
    int c = 0;
    while (c < static_cast<int>(s.size()) && s[static_cast<std::size_t>(c)] > 0) ++c;
    colour[static_cast<std::size_t>(v)] = c;
    colours = std::max(colours, c + 1);
    for (int u : adj[static_cast<std::size_t>(v)]) {
      const auto uu = static_cast<std::size_t>(u);
      if (colour[uu] >= 0) continue;
      queue.erase({-sat[uu], -deg[uu], key[uu], u});
      auto& su = seen[uu];
      if (static_cast<int>(su.size()) <= c) su.resize(static_cast<std::size_t>(c) + 1, 0);
      if (su[static_cast<std::size_t>(c)]++ == 0) ++sat[uu];
      --deg[uu];
      queue.emplace(-sat[uu], -deg[uu], key[uu], u);
    }
  }
  return colour;
}

double min_same_class_distance(const std::vector<Eigen::Vector2d>& p, const std::vector<int>& class_of, int k) {
  std::vector<std::vector<int>> members(static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < p.size(); ++i) members[static_cast<std::size_t>(class_of[i])].push_back(static_cast<int>(i));
  double best = std::numeric_limits<double>::infinity();
  for (const auto& m : members)  // sum of members^2 = n^2 / k: fine for thousands of LEDs
    for (std::size_t a = 0; a < m.size(); ++a)
      for (std::size_t b = a + 1; b < m.size(); ++b)
        best = std::min(best, (p[static_cast<std::size_t>(m[a])] - p[static_cast<std::size_t>(m[b])]).norm());
  return best;
}

}  // namespace

FrequencyBand frequency_band(const CameraModel& camera, double dz_m, double led_diameter_m,
                             const FrequencyBandOptions& o) {
  FrequencyBand band;
  band.relative_step = o.relative_step;
  // Low end: the design blob (an LED at the level camera's half-diagonal angle a) spans
  // fy d cos^2(a) / dz rows (range dz / cos a, the disc foreshortened by cos a); it must
  // show min_periods periods of 1 / (f row_time) rows.
  const double a = half_diagonal_fov_rad(camera);
  band.blob_rows = camera.fy * led_diameter_m * std::cos(a) * std::cos(a) / std::max(dz_m, 1e-3);
  band.f_min_hz = o.min_periods / (std::max(band.blob_rows, 1e-6) * camera.row_time_s);
  // High end: contrast |sinc(f T)| >= min_contrast (solved by bisection on f T in (0, 1)),
  // and the period at least min_period_rows rows.
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (lo + hi);
    (std::sin(kPi * m) / (kPi * m) >= o.min_contrast ? lo : hi) = m;
  }
  const double f_contrast = lo / camera.exposure_s;
  const double f_rows = 1.0 / (o.min_period_rows * camera.row_time_s);
  band.f_max_hz = std::min(f_contrast, f_rows);
  band.high_limit = f_contrast <= f_rows ? "contrast" : "row time";
  band.capacity = band.f_max_hz > band.f_min_hz
                      ? 1 + static_cast<int>(std::floor(std::log(band.f_max_hz / band.f_min_hz) /
                                                        std::log1p(o.relative_step)))
                      : 0;
  return band;
}

std::vector<double> spread_frequencies(const FrequencyBand& band, int k) {
  std::vector<double> f;
  if (k <= 0) return f;
  if (k == 1) return {std::sqrt(band.f_min_hz * band.f_max_hz)};
  const double ratio = std::pow(band.f_max_hz / band.f_min_hz, 1.0 / (k - 1));
  for (int i = 0; i < k; ++i) f.push_back(band.f_min_hz * std::pow(ratio, i));
  return f;
}

FrequencyPlan plan_frequency_classes(const std::vector<Eigen::Vector2d>& p, double conflict_distance_m,
                                     const FrequencyPlanOptions& o) {
  FrequencyPlan plan;
  plan.conflict_distance_m = conflict_distance_m;
  const std::size_t n = p.size();
  if (n == 0) return plan;
  std::mt19937_64 rng(o.seed);
  // Reuse distances are searched up to three conflict distances: k classes on a layout of
  // spacing s reach about s sqrt(k / 0.87), below 3 D for every k the band allows.
  const double reach = 3.0 * conflict_distance_m;
  const Neighbours near = neighbours_within(p, reach);
  const auto graph = [&](double r) {  // conflict graph "closer than r"
    std::vector<std::vector<int>> adj(n);
    for (std::size_t i = 0; i < n; ++i)
      for (const auto& [d, j] : near.of[i]) {
        if (d >= r) break;  // sorted by distance
        adj[i].push_back(j);
      }
    return adj;
  };
  // The fewest colours DSatur finds over a few seeds, and that colouring.
  const auto best_dsatur = [&](const std::vector<std::vector<int>>& adj, int& colours) {
    std::vector<int> best;
    colours = std::numeric_limits<int>::max();
    for (int attempt = 0; attempt < o.attempts; ++attempt) {
      int c = 0;
      auto colouring = dsatur(adj, rng, c);
      if (c < colours) {
        colours = c;
        best = std::move(colouring);
      }
    }
    return best;
  };
  int needed = 0;
  std::vector<int> colouring = best_dsatur(graph(conflict_distance_m), needed);
  plan.classes_needed = needed;
  const int k = o.classes > 0 ? o.classes : needed;
  if (k < needed)
    throw std::invalid_argument(std::to_string(k) + " classes are too few: the layout needs " + std::to_string(needed) +
                                " (LEDs closer than " + std::to_string(conflict_distance_m) + " m conflict)");
  plan.classes = k;

  // Largest reuse distance r with a k-colouring of "closer than r" (binary search over the
  // layout's distinct distances): extra classes buy distance between copies, which is
  // what lets the filter tell copies apart (capture radius = half of it).
  std::vector<double> cut;
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& [d, j] : near.of[i])
      if (d > conflict_distance_m) cut.push_back(d);
  std::sort(cut.begin(), cut.end());
  cut.erase(std::unique(cut.begin(), cut.end(), [](double a, double b) { return b - a < 1e-6; }), cut.end());
  double reuse = conflict_distance_m;
  std::size_t lo = 0, hi = cut.size();  // cut[lo - 1] feasible (or D), cut[hi] not tried
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    const double r = cut[mid] + 1e-6;  // "closer than r" includes the pairs at cut[mid]
    int c = 0;
    auto attempt = best_dsatur(graph(r), c);
    if (c <= k) {
      reuse = r;
      colouring = std::move(attempt);
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  // Break the lattice's period: each LED takes a class at random among those valid at the
  // reuse distance (no member closer than it), which keeps every copy that far apart. At
  // the largest reuse distance the colouring is often rigid (one valid class per LED, a
  // periodic tiling: alias 1.0), so the distance steps down through the layout's distances
  // until the shuffled colouring's alias fraction is at most options.max_alias.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::vector<char> valid(static_cast<std::size_t>(k));
  std::vector<int> candidates;
  const auto shuffle = [&](const std::vector<std::vector<int>>& adj, std::vector<int>& colours) {
    for (int pass = 0; pass < o.shuffle_passes; ++pass) {
      std::shuffle(order.begin(), order.end(), rng);
      for (std::size_t i : order) {
        std::fill(valid.begin(), valid.end(), 1);
        for (int j : adj[i]) valid[static_cast<std::size_t>(colours[static_cast<std::size_t>(j)])] = 0;
        candidates.clear();
        for (int c = 0; c < k; ++c)
          if (valid[static_cast<std::size_t>(c)]) candidates.push_back(c);
        if (!candidates.empty()) colours[i] = candidates[static_cast<std::size_t>(rng() % candidates.size())];
      }
    }
  };
  std::size_t step = lo;  // cut[step - 1] + 1e-6 == reuse when step > 0
  for (;;) {
    const auto adj = graph(reuse);
    shuffle(adj, colouring);
    const AliasReport alias = translational_alias(p, colouring, reach);
    plan.alias_fraction = alias.fraction;
    plan.alias_shift = alias.shift;
    if (alias.fraction <= o.max_alias || step == 0) break;
    --step;
    reuse = step == 0 ? conflict_distance_m : cut[step - 1] + 1e-6;
    int c = 0;
    colouring = best_dsatur(graph(reuse), c);  // feasible: a smaller distance than one that was
  }
  plan.class_of = std::move(colouring);
  plan.min_reuse_distance_m = min_same_class_distance(p, plan.class_of, k);
  return plan;
}

AliasReport translational_alias(const std::vector<Eigen::Vector2d>& p, const std::vector<int>& class_of,
                                double max_shift_m, double tolerance_m) {
  AliasReport report;
  const Neighbours near = neighbours_within(p, max_shift_m);
  // Per shift bin: how many LEDs land on an LED, and on one of their own class. Only the
  // half-plane of shifts (the opposite shift is the same alias).
  std::unordered_map<std::int64_t, std::pair<int, int>> bins;
  const auto bin = [&](const Eigen::Vector2d& s) {
    const auto ix = static_cast<std::int64_t>(std::llround(s.x() / tolerance_m));
    const auto iy = static_cast<std::int64_t>(std::llround(s.y() / tolerance_m));
    return std::pair<std::int64_t, std::int64_t>{ix, iy};
  };
  for (std::size_t i = 0; i < p.size(); ++i)
    for (const auto& [d, j] : near.of[i]) {
      const auto [ix, iy] = bin(p[static_cast<std::size_t>(j)] - p[i]);
      if (ix < 0 || (ix == 0 && iy <= 0)) continue;
      auto& b = bins[(ix << 32) ^ (iy & 0xffffffff)];
      ++b.first;
      if (class_of[i] == class_of[static_cast<std::size_t>(j)]) ++b.second;
    }
  const int min_overlap = std::max(20, static_cast<int>(p.size() / 10));
  for (const auto& [key, counts] : bins) {
    if (counts.first < min_overlap) continue;
    const double f = static_cast<double>(counts.second) / counts.first;
    if (f > report.fraction) {
      report.fraction = f;
      report.overlap = counts.first;
      const std::int64_t ix = key >> 32;
      const auto iy = static_cast<std::int32_t>(key & 0xffffffff);
      report.shift = Eigen::Vector2d(static_cast<double>(ix) * tolerance_m, static_cast<double>(iy) * tolerance_m);
    }
  }
  return report;
}

}  // namespace luxloc
