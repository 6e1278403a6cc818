#pragma once
// The error model of one UWB measurement (a time-of-flight range, optionally with an angle
// of arrival) and its log-likelihood.
//
// Line of sight: range error ~ N(0, range_sigma), bearing error ~ N(0, aoa_sigma).
// Non-line of sight (the direct path is blocked, the radio locks on a reflection): the
// measured range is LONGER than the true one — a one-sided positive bias — and the bearing
// points at the reflector. Robust model (docs/UWB_VO_CALIB.md "Models"):
//   p(r, theta | x) = (1 - eps) N(e_r; 0, s_r) N(e_theta; 0, s_theta)
//                   +      eps  ExGauss(e_r; s_r, mu_b) N(e_theta; 0, s_nlos)
//                   +      floor U(range) U(theta)
// with e_r = measured - predicted range, e_theta the wrapped bearing error, ExGauss the
// density of a Gaussian plus an exponential bias of mean mu_b (one-sided heavy tail: a
// large positive residual stays plausible, a large negative one does not), s_nlos a broad
// bearing spread (a reflection arrives from near the direct path's direction more often
// than from behind the anchor), U uniform densities over max_range and the circle: the
// floor keeps any single gross error from zeroing every particle. `gaussian` drops the
// mixture (seed A/B's plain weighting).
#include <cmath>
#include <numbers>

namespace luxloc {

enum class UwbLikelihood { gaussian, robust };

struct UwbNoiseModel {
  UwbLikelihood likelihood = UwbLikelihood::robust;
  double range_sigma_m = 0.10;   // LOS ranging noise, 1 sigma
  double aoa_sigma_rad = 0.05;   // LOS bearing noise, 1 sigma (~3 deg)
  double nlos_probability = 0.05;
  double nlos_bias_mean_m = 1.0;  // mean positive range bias of an NLOS measurement
  double nlos_aoa_sigma_rad = 0.5;  // bearing spread of an NLOS measurement
  double max_range_m = 30.0;      // support of the outlier floor
  double floor_probability = 1e-3;

  // Wraps an angle to (-pi, pi].
  static double wrap(double a) {
    a = std::remainder(a, 2.0 * std::numbers::pi);
    return a;
  }

  // log p(range error e_r), range only (anchors without AOA).
  double range_log_likelihood(double e_r) const {
    const double z = e_r / range_sigma_m;
    const double log_n = -0.5 * z * z - std::log(range_sigma_m * std::sqrt(2.0 * std::numbers::pi));
    if (likelihood == UwbLikelihood::gaussian) return log_n;
    return log_mix(std::log1p(-nlos_probability - floor_probability) + log_n,
                   std::log(nlos_probability) + log_exgauss(e_r), std::log(floor_probability / max_range_m));
  }

  // log p(range error e_r, bearing error e_theta) (a TOF + AOA measurement).
  double range_aoa_log_likelihood(double e_r, double e_theta) const {
    const double zr = e_r / range_sigma_m, zt = wrap(e_theta) / aoa_sigma_rad;
    const double log_n = -0.5 * (zr * zr + zt * zt) -
                         std::log(2.0 * std::numbers::pi * range_sigma_m * aoa_sigma_rad);
    if (likelihood == UwbLikelihood::gaussian) return log_n;
    const double log_u = -std::log(2.0 * std::numbers::pi);
    const double zn = wrap(e_theta) / nlos_aoa_sigma_rad;
    const double log_nlos_aoa = -0.5 * zn * zn - std::log(nlos_aoa_sigma_rad * std::sqrt(2.0 * std::numbers::pi));
    return log_mix(std::log1p(-nlos_probability - floor_probability) + log_n,
                   std::log(nlos_probability) + log_exgauss(e_r) + log_nlos_aoa,
                   std::log(floor_probability / max_range_m) + log_u);
  }

  // Exponentially modified Gaussian: e = n + b, n ~ N(0, s), b ~ Exp(mean mu):
  // f(e) = (l/2) exp((l/2)(l s^2 - 2e)) erfc((l s^2 - e) / (sqrt2 s)),  l = 1/mu.
  // Evaluated in log space with erfc's asymptote for large arguments (no underflow).
  double log_exgauss(double e) const {
    const double s = range_sigma_m, l = 1.0 / nlos_bias_mean_m;
    const double a = (l * s * s - e) / (std::numbers::sqrt2 * s);
    const double base = std::log(0.5 * l) + 0.5 * l * (l * s * s - 2.0 * e);
    if (a < 5.0) return base + std::log(std::erfc(a));
    // erfc(a) ~ exp(-a^2) / (a sqrt(pi)) for large a.
    return base - a * a - std::log(a * std::sqrt(std::numbers::pi));
  }

 private:
  static double log_mix(double a, double b, double c) {
    const double m = std::fmax(a, std::fmax(b, c));
    return m + std::log(std::exp(a - m) + std::exp(b - m) + std::exp(c - m));
  }
};

}  // namespace luxloc
