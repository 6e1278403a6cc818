#include "core/sim/pace_drift.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace luxloc::sim {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kPanel = PaceDrift::kPanel;

// 8-point Gauss-Legendre on [-1, 1] (Abramowitz & Stegun 25.4.30).
constexpr std::array<double, 4> kNode = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                         0.9602898564975363};
constexpr std::array<double, 4> kWeight = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                           0.1012285362903763};

// int_a^b f by 8-point Gauss-Legendre.
template <class F>
double gauss8(const F& f, double a, double b) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (std::size_t i = 0; i < kNode.size(); ++i)
    sum += kWeight[i] * (f(mid - half * kNode[i]) + f(mid + half * kNode[i]));
  return half * sum;
}

}  // namespace

PaceDrift::PaceDrift(std::vector<PaceWave> waves, double f0, double m, double horizon_s, std::vector<PaceDip> dips)
    : waves_(std::move(waves)), dips_(std::move(dips)), f0_(f0), m_(m), horizon_(horizon_s) {
  for (const PaceDip& d : dips_)
    if (!(d.depth >= 0.0 && d.depth < 1.0) || !(d.ramp_s > 0.0) || !(d.duration_s >= 2.0 * d.ramp_s) ||
        !std::isfinite(d.start_s + d.duration_s))
      throw std::invalid_argument("PaceDrift: a dip needs 0 <= depth < 1 and at least two ramps' duration");
  double total = 0.0;
  for (const PaceWave& w : waves_) {
    total += std::abs(w.amplitude);
    if (!(w.period_s >= 5.0) || !std::isfinite(w.period_s) || !std::isfinite(w.phase_rad))
      throw std::invalid_argument("PaceDrift: wave periods must be >= 5 s");
  }
  if (!(total < 0.5) || !(f0 > 0.0) || !(std::abs(m) < 1.0) || !(horizon_s > 0.0) || !std::isfinite(horizon_s))
    throw std::invalid_argument("PaceDrift: amplitudes must sum below 0.5, cadence > 0, |m| < 1, horizon > 0");
  const std::size_t n = static_cast<std::size_t>(std::ceil(horizon_s / kPanel));
  horizon_ = n * kPanel;
  steps_at_.assign(n + 1, 0.0);
  distance_at_.assign(n + 1, 0.0);
  // N first (distance_rate reads it through steps()), then D.
  for (std::size_t k = 0; k < n; ++k)
    steps_at_[k + 1] = steps_at_[k] + f0_ * gauss8([this](double g) { return cadence_factor(g).v; },
                                                    k * kPanel, (k + 1) * kPanel);
  for (std::size_t k = 0; k < n; ++k)
    distance_at_[k + 1] =
        distance_at_[k] + gauss8([this](double g) { return distance_rate(g); }, k * kPanel, (k + 1) * kPanel);
}

Jet PaceDrift::speed_factor(double G) const {
  Jet q = Jet::constant(1.0);
  for (const PaceWave& w : waves_) {
    const double k = kTwoPi / w.period_s, s = std::sin(k * G + w.phase_rad), c = std::cos(k * G + w.phase_rad);
    q = q + Jet{w.amplitude * s, w.amplitude * k * c, -w.amplitude * k * k * s};
  }
  for (const PaceDip& d : dips_) q = q * (1.0 - d.depth * plateau(G, d.start_s, d.duration_s, d.ramp_s));
  return q;
}

// sqrt q: (sqrt q)' = q' / (2 c), (sqrt q)'' = q'' / (2 c) - q'^2 / (4 c^3).
Jet PaceDrift::cadence_factor(double G) const {
  const Jet q = speed_factor(G);
  const double c = std::sqrt(q.v);
  return {c, q.d / (2.0 * c), q.dd / (2.0 * c) - q.d * q.d / (4.0 * c * c * c)};
}

Jet PaceDrift::length_factor(double G) const { return cadence_factor(G); }

double PaceDrift::steps(double G) const {
  if (!(G >= 0.0 && G <= horizon_))
    throw std::out_of_range("PaceDrift: walked time " + std::to_string(G) + " s beyond the drift's " +
                            std::to_string(horizon_) + " s");
  const std::size_t k = static_cast<std::size_t>(G / kPanel);
  return steps_at_[k] + f0_ * gauss8([this](double g) { return cadence_factor(g).v; }, k * kPanel, G);
}

// l c = q, so D' = q (1 + m cos 2 pi N).
double PaceDrift::distance_rate(double G) const {
  return speed_factor(G).v * (1.0 + m_ * std::cos(kTwoPi * steps(G)));
}

Jet PaceDrift::distance(double G) const {
  const double N = steps(G);  // checks the horizon (before G indexes the table)
  const std::size_t k = static_cast<std::size_t>(G / kPanel);
  const double D = distance_at_[k] + gauss8([this](double g) { return distance_rate(g); }, k * kPanel, G);
  const Jet q = speed_factor(G);
  const double phi = kTwoPi * N, dphi = kTwoPi * f0_ * cadence_factor(G).v;
  const double mod = 1.0 + m_ * std::cos(phi);
  return {D, q.v * mod, q.d * mod - q.v * m_ * std::sin(phi) * dphi};
}

}  // namespace luxloc::sim
