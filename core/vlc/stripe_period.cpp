#include "core/vlc/stripe_period.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace luxloc {
namespace {

constexpr int kMaxTrend = 2;

// Weighted least-squares periodogram of one profile: the power a sinusoid of frequency nu
// (cycles/row) explains after a polynomial trend (Frisch-Waugh: the sinusoid's columns
// are projected off the trend basis, so only 2x2 systems are solved per frequency).
class Periodogram {
 public:
  Periodogram(std::span<const double> y, std::span<const double> w, int trend_order) : y_(y), w_(w) {
    first_ = 0;
    last_ = static_cast<int>(y.size()) - 1;
    while (first_ <= last_ && weight(first_) <= 0.0) ++first_;
    while (last_ >= first_ && weight(last_) <= 0.0) --last_;
    for (int v = first_; v <= last_; ++v)
      if (weight(v) > 0.0 && std::isfinite(y[static_cast<std::size_t>(v)])) {
        ++count_;
        wsum_ += weight(v);
      }
    trend_ = std::clamp(trend_order, 0, kMaxTrend);
    if (count_ < trend_ + 4) return;
    // Orthonormal trend basis (Gram-Schmidt under the weighted inner product) on the
    // rows first_..last_, in x = scaled row so the powers stay well conditioned.
    const int n = last_ - first_ + 1;
    const double mid = 0.5 * (first_ + last_), half = std::max(0.5 * (last_ - first_), 1.0);
    q_.assign(static_cast<std::size_t>(n * (trend_ + 1)), 0.0);
    for (int j = 0; j <= trend_; ++j) {
      double* qj = &q_[static_cast<std::size_t>(j * n)];
      for (int i = 0; i < n; ++i) qj[i] = std::pow((first_ + i - mid) / half, j);
      for (int k = 0; k < j; ++k) {
        const double* qk = &q_[static_cast<std::size_t>(k * n)];
        const double d = dot(qj, qk);
        for (int i = 0; i < n; ++i) qj[i] -= d * qk[i];
      }
      const double nn = std::sqrt(dot(qj, qj));
      if (!(nn > 1e-12)) return;
      for (int i = 0; i < n; ++i) qj[i] /= nn;
    }
    // Detrended profile y' and its weighted energy.
    yd_.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) yd_[static_cast<std::size_t>(i)] = usable(first_ + i) ? y[static_cast<std::size_t>(first_ + i)] : 0.0;
    for (int j = 0; j <= trend_; ++j) {
      const double* qj = &q_[static_cast<std::size_t>(j * n)];
      const double d = dot(yd_.data(), qj);
      for (int i = 0; i < n; ++i) yd_[static_cast<std::size_t>(i)] -= d * qj[i];
    }
    energy_ = dot(yd_.data(), yd_.data());
    double raw = 0.0;  // a flat profile leaves only rounding after the detrend
    for (int i = 0; i < n; ++i)
      if (usable(first_ + i)) raw += weight(first_ + i) * y[static_cast<std::size_t>(first_ + i)] * y[static_cast<std::size_t>(first_ + i)];
    ok_ = energy_ > 1e-20 * raw && energy_ > 0.0 && std::isfinite(energy_);
  }

  bool ok() const { return ok_; }
  int first() const { return first_; }
  int last() const { return last_; }
  int count() const { return count_; }
  int trend() const { return trend_; }
  double energy() const { return energy_; }
  double weight_sum() const { return wsum_; }

  struct Fit {
    double power = 0.0, a = 0.0, b = 0.0;
  };

  // Power explained by cos/sin at nu (cycles/row), and their coefficients.
  Fit eval(double nu) const {
    Fit f;
    const int n = last_ - first_ + 1;
    const double step = 2.0 * std::numbers::pi * nu;
    const double cd = std::cos(step), sd = std::sin(step);
    double c = std::cos(step * first_), s = std::sin(step * first_);
    double cy = 0, sy = 0, cc = 0, ss = 0, cs = 0;
    std::array<double, kMaxTrend + 1> qc{}, qs{};
    for (int i = 0; i < n; ++i) {
      const int v = first_ + i;
      if (usable(v)) {
        const double w = weight(v);
        const double wc = w * c, ws = w * s;
        cy += wc * yd_[static_cast<std::size_t>(i)];
        sy += ws * yd_[static_cast<std::size_t>(i)];
        cc += wc * c;
        ss += ws * s;
        cs += wc * s;
        for (int j = 0; j <= trend_; ++j) {
          const double q = q_[static_cast<std::size_t>(j * n + i)];
          qc[static_cast<std::size_t>(j)] += wc * q;
          qs[static_cast<std::size_t>(j)] += ws * q;
        }
      }
      const double cn = c * cd - s * sd;  // rotate to the next row
      s = s * cd + c * sd;
      c = cn;
    }
    for (int j = 0; j <= trend_; ++j) {
      const auto k = static_cast<std::size_t>(j);
      cc -= qc[k] * qc[k];
      ss -= qs[k] * qs[k];
      cs -= qc[k] * qs[k];
    }
    const double det = cc * ss - cs * cs;
    if (!(det > 1e-12 * std::max(cc * ss, 1e-300))) return f;
    f.a = (ss * cy - cs * sy) / det;
    f.b = (cc * sy - cs * cy) / det;
    f.power = std::max(0.0, f.a * cy + f.b * sy);
    return f;
  }

 private:
  double weight(int v) const { return w_.empty() ? 1.0 : w_[static_cast<std::size_t>(v)]; }
  bool usable(int v) const { return weight(v) > 0.0 && std::isfinite(y_[static_cast<std::size_t>(v)]); }
  double dot(const double* a, const double* b) const {
    double d = 0;
    for (int i = 0, n = last_ - first_ + 1; i < n; ++i)
      if (usable(first_ + i)) d += weight(first_ + i) * a[i] * b[i];
    return d;
  }

  std::span<const double> y_, w_;
  int first_ = 0, last_ = -1, count_ = 0, trend_ = 0;
  double wsum_ = 0.0, energy_ = 0.0;
  bool ok_ = false;
  std::vector<double> q_, yd_;
};

// Golden-section search for the maximum of power(nu) in [lo, hi].
template <class Power>
double golden_max(const Power& power_at, double lo, double hi, int iterations = 40) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = lo, b = hi;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = power_at(x1), f2 = power_at(x2);
  for (int i = 0; i < iterations && (b - a) > 1e-12; ++i) {
    if (f1 < f2) {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = power_at(x2);
    } else {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = power_at(x1);
    }
  }
  return 0.5 * (a + b);
}

double refine_peak(const Periodogram& pg, double lo, double hi) {
  return golden_max([&pg](double nu) { return pg.eval(nu).power; }, lo, hi);
}

// Best local peak within [lo, hi]: a coarse scan, then golden refinement around it.
double local_peak(const Periodogram& pg, double lo, double hi) {
  constexpr int kScan = 12;
  double best = lo, best_p = -1;
  for (int i = 0; i <= kScan; ++i) {
    const double nu = lo + (hi - lo) * i / kScan;
    const double p = pg.eval(nu).power;
    if (p > best_p) {
      best_p = p;
      best = nu;
    }
  }
  const double h = (hi - lo) / kScan;
  return refine_peak(pg, std::max(lo, best - h), std::min(hi, best + h));
}

}  // namespace

StripePeriodEstimate estimate_stripe_period(std::span<const double> profile, std::span<const double> weights,
                                            double min_period, double max_period,
                                            const StripePeriodOptions& options) {
  StripePeriodEstimate est;
  if (!weights.empty() && weights.size() != profile.size()) return est;
  min_period = std::max(min_period, 2.0);  // Nyquist
  if (!(max_period > min_period) || !std::isfinite(max_period)) return est;

  const Periodogram pg(profile, weights, options.trend_order);
  if (!pg.ok()) return est;
  const double span = pg.last() - pg.first() + 1;
  est.span_rows = span;
  const double nu_lo = 1.0 / max_period, nu_hi = 1.0 / min_period;
  const double step = 1.0 / (std::max(options.grid_oversampling, 1.0) * span);
  const int n_grid = std::max(3, static_cast<int>(std::ceil((nu_hi - nu_lo) / step)) + 1);
  const double dnu = (nu_hi - nu_lo) / (n_grid - 1);

  std::vector<double> grid_power(static_cast<std::size_t>(n_grid));
  int k_best = 0;
  for (int k = 0; k < n_grid; ++k) {
    grid_power[static_cast<std::size_t>(k)] = pg.eval(nu_lo + k * dnu).power;
    if (grid_power[static_cast<std::size_t>(k)] > grid_power[static_cast<std::size_t>(k_best)]) k_best = k;
  }
  if (!(grid_power[static_cast<std::size_t>(k_best)] > 0.0)) return est;
  double nu = refine_peak(pg, nu_lo + std::max(0, k_best - 1) * dnu, nu_lo + std::min(n_grid - 1, k_best + 1) * dnu);
  double power = pg.eval(nu).power;

  // A harmonic of a square wave must not be taken for its fundamental (SEEDS A S202):
  // if nu/k is in range and explains a comparable share, it is the fundamental.
  const double lobe = 1.0 / span;
  int chosen_k = 1;
  double chosen_nu = nu, chosen_power = power;
  for (int k = 2; k <= options.max_subharmonic; ++k) {
    // Only a resolvable sub-harmonic inside the range, and only a true local maximum there
    // (not the flank of the main lobe) counts.
    const double nk = nu / k;
    if (nk < nu_lo) break;
    if (nu - nk < lobe) continue;
    const double lo = std::max(nu_lo, nk - 0.5 * lobe), hi = std::min(nu_hi, nk + 0.5 * lobe);
    if (!(hi > lo)) continue;
    const double cand = local_peak(pg, lo, hi);
    const double pk = pg.eval(cand).power;
    const double eps = 1e-3 * (hi - lo);
    const bool is_peak = pk > pg.eval(std::max(nu_lo, cand - eps)).power && pk >= pg.eval(cand + eps).power;
    if (is_peak && pk >= options.subharmonic_power_ratio * power && pk > (chosen_k == 1 ? 0.0 : chosen_power)) {
      chosen_k = k;
      chosen_nu = cand;
      chosen_power = pk;
    }
  }
  nu = chosen_nu;
  power = chosen_power;
  est.subharmonic = chosen_k;

  // Largest power away from the main lobe and from the multiples of the chosen frequency.
  double side = 0.0;
  for (int k = 0; k < n_grid; ++k) {
    const double f = nu_lo + k * dnu;
    const double m = std::max(1.0, std::round(f / nu));
    if (std::abs(f - m * nu) < lobe) continue;
    side = std::max(side, grid_power[static_cast<std::size_t>(k)]);
  }
  est.peak_to_sidelobe = side > 0.0 ? power / side : 1e6;

  const Periodogram::Fit fit = pg.eval(nu);
  est.valid = true;
  est.cycles_per_row = nu;
  est.period_rows = 1.0 / nu;
  est.explained = std::clamp(power / pg.energy(), 0.0, 1.0);
  est.amplitude = std::hypot(fit.a, fit.b);
  est.phase_rad = std::atan2(fit.b, fit.a);
  est.at_range_edge = (nu - nu_lo) < 1e-6 * nu_lo || (nu_hi - nu) < 1e-6 * nu_hi;
  // Cramer-Rao bound for a sinusoid's frequency in white noise: var(omega) = 12 s^2 /
  // (A^2 N (N^2 - 1)), with s^2 the residual variance per unit weight.
  const double n = pg.count();
  const double dof = std::max(1.0, n - (pg.trend() + 1) - 3);
  const double resid_var = std::max(0.0, pg.energy() - power) / pg.weight_sum() * n / dof;
  const double a2 = std::max(est.amplitude * est.amplitude, 1e-300);
  const double var_omega = 12.0 * resid_var / (a2 * n * std::max(n * n - 1.0, 1.0));
  const double sigma_nu = std::sqrt(var_omega) / (2.0 * std::numbers::pi);
  est.period_sigma_rows = sigma_nu / (nu * nu);
  return est;
}

EdgePeriodEstimate estimate_period_from_edges(std::span<const double> y, std::span<const double> w, double duty,
                                              double min_period, double max_period, double end_margin_rows,
                                              double edge_sigma_rows) {
  EdgePeriodEstimate out;
  const int n = static_cast<int>(y.size());
  const auto ok = [&](int i) { return i >= 0 && i < n && (w.empty() || w[static_cast<std::size_t>(i)] > 0); };
  int a = 0, b = n - 1;
  while (a <= b && !ok(a)) ++a;
  while (b >= a && !ok(b)) --b;
  if (b - a < 4 || !(duty > 0.05 && duty < 0.95)) return out;
  double lo = 1e300, hi = -1e300;
  for (int i = a; i <= b; ++i)
    if (ok(i)) {
      lo = std::min(lo, y[static_cast<std::size_t>(i)]);
      hi = std::max(hi, y[static_cast<std::size_t>(i)]);
    }
  if (!(hi > lo)) return out;
  const auto x = [&](int i) { return (y[static_cast<std::size_t>(i)] - lo) / (hi - lo); };
  struct Edge {
    double pos;
    bool rising;
  };
  std::vector<Edge> edges;
  int state = 0, last_state_row = a;  // -1 low, +1 high
  for (int i = a; i <= b; ++i) {
    if (!ok(i)) {
      state = 0;  // a gap: no edge across it
      continue;
    }
    const double v = x(i);
    const int s = v > 0.65 ? 1 : v < 0.35 ? -1 : 0;
    if (s == 0) continue;
    if (state != 0 && s != state) {
      // The 50 % crossing between the last row of the old state and this one.
      for (int k = last_state_row; k < i; ++k) {
        if (!ok(k) || !ok(k + 1)) continue;
        const double x0 = x(k), x1 = x(k + 1);
        if ((x0 - 0.5) * (x1 - 0.5) <= 0 && x0 != x1) {
          edges.push_back({k + (0.5 - x0) / (x1 - x0), s > 0});
          break;
        }
      }
    }
    state = s;
    last_state_row = i;
  }
  std::vector<Edge> inner;
  for (const Edge& e : edges)
    if (e.pos >= a + end_margin_rows && e.pos <= b - end_margin_rows) inner.push_back(e);
  out.edges = static_cast<int>(inner.size());
  if (inner.size() < 2) return out;
  double period = 0;
  if (inner.size() == 2) {
    const double s = inner[1].pos - inner[0].pos;
    period = inner[0].rising ? s / duty : s / (1.0 - duty);  // rising then falling: a bright stripe
    out.period_sigma_rows = std::sqrt(2.0) * edge_sigma_rows / (inner[0].rising ? duty : 1.0 - duty);
  } else {
    double sum = 0;
    int cnt = 0;
    for (std::size_t i = 0; i + 2 < inner.size(); ++i) {
      sum += inner[i + 2].pos - inner[i].pos;
      ++cnt;
    }
    period = sum / cnt;
    for (std::size_t i = 0; i + 2 < inner.size(); ++i)
      if (std::abs(inner[i + 2].pos - inner[i].pos - period) > 0.1 * period) return out;
    out.period_sigma_rows = std::sqrt(2.0) * edge_sigma_rows / std::sqrt(static_cast<double>(cnt));
  }
  if (!(period >= min_period && period <= max_period)) return out;
  // Self-consistency: the stripes before the first and after the last edge must end where
  // the period says; an edge predicted well inside the profile but not found means the
  // edges were not the stripes' (noise, the rim, a merged blob).
  const double lo_end = a + end_margin_rows + 0.1 * period, hi_end = b - end_margin_rows - 0.1 * period;
  const Edge& first = inner.front();
  const Edge& last = inner.back();
  const double before = first.rising ? (1.0 - duty) * period : duty * period;  // stripe before a rising edge is dark
  const double after = last.rising ? duty * period : (1.0 - duty) * period;    // after a rising edge: bright
  if (first.pos - before > lo_end || last.pos + after < hi_end) return out;
  out.period_rows = period;
  out.valid = true;
  return out;
}

}  // namespace luxloc
