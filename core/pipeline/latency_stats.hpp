#pragma once
// Input-to-output latency of poses: the age of the newest input a pose used, from its
// arrival in the source thread to the moment the pose is handed to the sinks (steady
// clock; PoseEstimate::latency_s). LatencyHistogram summarises a whole run in fixed
// memory (log-spaced bins, 2 % wide, 1 us .. 100 s); LatencyWindow the last few thousand
// poses for the live views (status line, MQTT status, web page).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace luxloc {

struct LatencySummary {
  std::uint64_t count = 0;
  double p50_s = std::numeric_limits<double>::quiet_NaN();
  double p99_s = std::numeric_limits<double>::quiet_NaN();
  double max_s = std::numeric_limits<double>::quiet_NaN();
};

class LatencyHistogram {
 public:
  void add(double latency_s) {
    if (!std::isfinite(latency_s)) return;
    ++count_;
    max_s_ = std::max(max_s_, latency_s);
    ++bins_[bin(latency_s)];
  }
  LatencySummary summary() const {
    LatencySummary s;
    s.count = count_;
    if (count_ == 0) return s;
    s.p50_s = quantile(0.50);
    s.p99_s = quantile(0.99);
    s.max_s = max_s_;
    return s;
  }

 private:
  static constexpr double kMin = 1e-6, kGrowth = 1.02;
  static constexpr std::size_t kBins = 932;  // 1 us * 1.02^931 ~ 100 s
  static std::size_t bin(double s) {
    if (s <= kMin) return 0;
    const double b = std::log(s / kMin) / std::log(kGrowth);
    return std::min<std::size_t>(kBins - 1, static_cast<std::size_t>(b));
  }
  // The upper edge of the bin holding the q-quantile (never above the maximum seen).
  double quantile(double q) const {
    const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_)));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
      seen += bins_[i];
      if (seen >= std::max<std::uint64_t>(rank, 1))
        return std::min(max_s_, kMin * std::pow(kGrowth, static_cast<double>(i + 1)));
    }
    return max_s_;
  }
  std::array<std::uint64_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  double max_s_ = 0.0;
};

// The last `capacity` latencies (a ring), exact percentiles over them.
class LatencyWindow {
 public:
  explicit LatencyWindow(std::size_t capacity = 2048) : capacity_(capacity) { values_.reserve(capacity); }
  void add(double latency_s) {
    if (!std::isfinite(latency_s)) return;
    if (values_.size() < capacity_)
      values_.push_back(latency_s);
    else
      values_[next_++ % capacity_] = latency_s;
  }
  LatencySummary summary() const {
    LatencySummary s;
    s.count = values_.size();
    if (values_.empty()) return s;
    std::vector<double> v = values_;
    const auto at = [&v](double q) {
      const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1;
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
      return v[k];
    };
    s.p50_s = at(0.50);
    s.p99_s = at(0.99);
    s.max_s = *std::max_element(v.begin(), v.end());
    return s;
  }

 private:
  std::size_t capacity_;
  std::size_t next_ = 0;
  std::vector<double> values_;
};

}  // namespace luxloc
