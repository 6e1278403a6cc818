#pragma once
// A persistent bias in the absolute fixes' innovations, for the reported sigma (issue 12
// part 3, "honest uncertainty"). A consistent filter's innovations nu = z - p (before the
// correction) are white with covariance S = P + R, so their mean over n fixes has covariance
// S / n. When the motion model is systematically wrong for seconds (a walker whose step
// length or walking direction the per-particle gait has not learnt yet), the filter lags
// its fixes: the innovations share a sign, their mean stands out of S / n, and the filter's
// own spread (which only knows the motion model's noise) is smaller than its error. This is
// the covariance-matching test of adaptive filtering (Mehra 1972; Mohamed & Schwarz 1999,
// "Adaptive Kalman filtering for INS/GPS", innovation-based estimation), used here to
// inflate the reported covariance only: the filter's state and its weighing are unchanged.
//   mean   m = sum_i w_i nu_i / sum_i w_i,   w_i = exp(-(t - t_i) / tau)   (per axis)
//   var(m) = (sum_i w_i S_i / sum_i w_i) / n_eff,   n_eff = (sum w)^2 / sum w^2
//   extra variance per axis = max(0, m^2 - excess_share * var(m))
#include <Eigen/Core>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct InnovationBiasOptions {
  bool enabled = true;
  // Memory of the mean innovation, s. Chosen on tuning seeds (`--walker random`, consumer
  // IMU; IMU + 1 Hz fixes of 0.5 m, seeds 1-10 and 41-60; IMU + one UWB station, the same
  // seeds): see FusionOptions::innovation_bias and docs/MOTION.md "Honest sigma".
  double time_constant_s = 5.0;
  // The part of m^2 explained by the fixes' own noise (var(m)) that is not added: 1 takes
  // the expected share away exactly (an unbiased estimate of the squared bias).
  double excess_share = 1.0;
};

class InnovationBias {
 public:
  explicit InnovationBias(const InnovationBiasOptions& options = {}) : options_(options) {}
  // One fix's innovation (fix minus the estimate before it weighed) and its predicted
  // covariance (the estimate's plus the fix's). Non-finite values are ignored.
  void add(TimeNs t, const Eigen::Vector2d& nu, const Eigen::Matrix2d& S);
  // Variance (m^2) per axis that the reported sigma_x / sigma_y carry besides the filter's.
  Eigen::Vector2d extra_variance() const { return extra_; }
  Eigen::Vector2d mean_innovation() const;
  void reset();

 private:
  InnovationBiasOptions options_;
  std::optional<TimeNs> t_last_;
  double w_sum_ = 0.0, w2_sum_ = 0.0;
  Eigen::Vector2d nu_sum_ = Eigen::Vector2d::Zero(), s_sum_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d extra_ = Eigen::Vector2d::Zero();
};

}  // namespace luxloc
