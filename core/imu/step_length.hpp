#pragma once
// Step length l_k of SEEDS.md A (S1) from what the step detector saw.
// - weinberg: l = K (a_max - a_min)^(1/4) (Weinberg, Analog Devices AN-602, 2002), with the
//   swing of the smoothed vertical acceleration over the step, in m/s^2. K depends on the
//   walker and on where the device is carried: calibrate it by walking a known distance D
//   (K = D / sum of swing^(1/4), see StepLengthModel::calibrate_weinberg).
// - cadence: l = a + b (f - 1.79 Hz), the linear step-frequency model for a 1.75 m adult
//   (Tian et al., 2015: a = 0.7 m, b = 0.227 m s); f = 1 / interval.
// - constant: l = a.
// Every model is clamped to [min_m, max_m]. The cadence model gives a first step after a
// stop (no interval known) its nominal length a.
#include <string>
#include <vector>

#include "core/imu/step_detector.hpp"

namespace luxloc {

enum class StepLengthKind { weinberg, cadence, constant };

struct StepLengthOptions {
  StepLengthKind kind = StepLengthKind::weinberg;
  double weinberg_k = 0.5;      // m per (m/s^2)^(1/4): a typical hand-held value, calibrate per user
  double a_m = 0.7;             // cadence: length at 1.79 Hz; constant: the length
  double b_m_s = 0.227;         // cadence: metres per Hz
  double min_m = 0.2, max_m = 1.5;
  double sigma_fraction = 0.1;  // 1-sigma of a step length as a fraction of it
};

// Parses "weinberg" / "cadence" / "constant"; throws std::invalid_argument otherwise.
StepLengthKind parse_step_length_kind(const std::string& name);

class StepLengthModel {
 public:
  explicit StepLengthModel(const StepLengthOptions& options = {}) : options_(options) {}
  double length_m(const DetectedStep& step) const;
  double sigma_m(double length_m) const { return options_.sigma_fraction * length_m; }
  // K such that the given steps add up to `distance_m` (Weinberg); NaN without steps.
  static double calibrate_weinberg(const std::vector<DetectedStep>& steps, double distance_m);
  const StepLengthOptions& options() const { return options_; }

 private:
  StepLengthOptions options_;
};

}  // namespace luxloc
