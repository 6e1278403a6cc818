#pragma once
// Random-particle injection for kidnapped-device recovery (Augmented MCL, Thrun et al.
// "Probabilistic Robotics" 8.3.5, ROS AMCL's recovery_alpha_slow/fast): track a slow and a
// fast running average of the measurement likelihood; when the fast one drops below the
// slow one (the device stopped matching where the filter thinks it is), replace each
// particle at resampling with a uniformly drawn one with probability 1 - w_fast / w_slow.
// The mean likelihood includes the measurement density's constant (ParticleFilter::correct),
// so fixes of different sigma compare; generic likelihoods (tight coupling) should too.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace luxloc {

struct InjectionOptions {
  bool enabled = false;
  double alpha_slow = 0.001;  // AMCL's suggested values
  double alpha_fast = 0.1;
  // Where a device can be (the LED map's extent): injected particles are drawn uniformly
  // inside. Empty: no injection.
  Eigen::AlignedBox2d region;
  double max_probability = 1.0;  // cap on the injected fraction per resampling
};

// The averages are kept in log space (log-sum-exp smoothing): a kidnapped device's
// likelihoods (exp(-20000) for a 10 m jump at 5 cm) would underflow a linear average.
class LikelihoodAverages {
 public:
  // avg_log_likelihood: log of the prior-weighted mean likelihood of one correction.
  void update(double avg_log_likelihood, const InjectionOptions& o) {
    if (!std::isfinite(avg_log_likelihood)) return;
    if (!set_) {
      log_slow_ = log_fast_ = avg_log_likelihood;  // first correction (or after a reset)
      set_ = true;
      return;
    }
    log_slow_ = smooth(log_slow_, avg_log_likelihood, o.alpha_slow);
    log_fast_ = smooth(log_fast_, avg_log_likelihood, o.alpha_fast);
  }
  double injection_probability(const InjectionOptions& o) const {
    if (!set_) return 0.0;
    return std::clamp(1.0 - std::exp(log_fast_ - log_slow_), 0.0, o.max_probability);
  }
  // AMCL resets both after injecting, so recovery does not spiral into randomness.
  void reset() { set_ = false; }
  double log_w_slow() const { return log_slow_; }
  double log_w_fast() const { return log_fast_; }

 private:
  // log((1 - a) exp(avg) + a exp(x))
  static double smooth(double avg, double x, double a) {
    a = std::clamp(a, 0.0, 1.0);
    if (a <= 0.0) return avg;
    if (a >= 1.0) return x;
    const double p = std::log1p(-a) + avg, q = std::log(a) + x;
    const double hi = std::max(p, q);
    return hi + std::log1p(std::exp(std::min(p, q) - hi));
  }
  double log_slow_ = 0.0, log_fast_ = 0.0;
  bool set_ = false;
};

}  // namespace luxloc
