#pragma once
// Scores detected steps against true heel strikes (the simulator's steps.csv): each true
// step is matched to the nearest unused detection within `tolerance_s`; detections left over
// are false steps. Greedy in time order, which is optimal when steps are further apart
// than twice the tolerance (they are: >= 0.3 s apart, tolerance 0.15 s).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace luxloc {

struct StepMatch {
  std::size_t truth = 0, detected = 0, matched = 0;
  double max_offset_s = 0.0;  // largest |detected - true| among matches
  double recall() const { return truth ? static_cast<double>(matched) / static_cast<double>(truth) : 1.0; }
  std::size_t false_steps() const { return detected - matched; }
  double false_rate() const { return detected ? static_cast<double>(false_steps()) / static_cast<double>(detected) : 0.0; }
};

inline StepMatch match_steps(const std::vector<double>& detected_s, const std::vector<double>& truth_s,
                             double tolerance_s = 0.15) {
  StepMatch m;
  m.truth = truth_s.size();
  m.detected = detected_s.size();
  std::vector<bool> used(detected_s.size(), false);
  std::size_t start = 0;
  for (const double t : truth_s) {
    while (start < detected_s.size() && detected_s[start] < t - tolerance_s) ++start;
    std::size_t best = detected_s.size();
    double best_d = tolerance_s;
    for (std::size_t i = start; i < detected_s.size() && detected_s[i] <= t + tolerance_s; ++i) {
      const double d = std::abs(detected_s[i] - t);
      if (!used[i] && d <= best_d) {
        best = i;
        best_d = d;
      }
    }
    if (best < detected_s.size()) {
      used[best] = true;
      ++m.matched;
      m.max_offset_s = std::max(m.max_offset_s, best_d);
    }
  }
  return m;
}

}  // namespace luxloc
