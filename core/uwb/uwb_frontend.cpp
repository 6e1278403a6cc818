#include "core/uwb/uwb_frontend.hpp"

#include <cmath>

#include "core/uwb/tof_aoa_fix.hpp"

namespace luxloc {

UwbFrontend::UwbFrontend(const UwbOptions& options, UwbAnchorTable anchors, double z_B)
    : options_(options), anchors_(std::move(anchors)), z_B_(z_B) {
  options_.multilateration.range_sigma_m = options_.noise.range_sigma_m;
}

std::optional<UwbRangeLikelihood> UwbFrontend::likelihood(const UwbSample& s) {
  ++stats_.samples;
  if (!std::isfinite(s.range_m) || s.range_m < 0.0 || std::isinf(s.aoa_rad)) {
    ++stats_.rejected;
    return std::nullopt;
  }
  if (anchors_.learn(s.anchor, s.p_AinW)) ++stats_.learnt_anchors;
  const std::optional<Eigen::Vector3d> a = anchors_.find(s.anchor);
  if (!a) {
    ++stats_.unknown_anchor;
    return std::nullopt;
  }
  return UwbRangeLikelihood(*a, z_B_, anchors_.corrected_range(s.anchor, s.range_m), s.aoa_rad, options_.noise);
}

std::optional<PositionMeasurement> UwbFrontend::fix(const UwbSample& measured) {
  UwbSample s = measured;
  s.range_m = anchors_.corrected_range(s.anchor, s.range_m);
  const std::optional<Eigen::Vector3d> a = anchors_.find(s.anchor);
  if (!a || !std::isfinite(s.range_m) || s.range_m < 0.0) return std::nullopt;
  if (std::isfinite(s.aoa_rad)) {
    std::optional<PositionMeasurement> m = tof_aoa_fix(s, *a, z_B_, options_.noise);
    if (m) ++stats_.fixes;
    return m;
  }
  std::optional<PositionMeasurement> done;
  // A range beyond the window of the open group closes it first.
  if (!group_.empty() && ns_to_seconds(s.t - group_t0_) > options_.group_window_s) done = flush_group();
  if (group_.empty()) group_t0_ = s.t;
  bool replaced = false;
  for (auto& [id, r] : group_)
    if (id == s.anchor) {
      r.range_m = s.range_m;  // the newer range of the same anchor
      replaced = true;
    }
  if (!replaced) group_.push_back({s.anchor, RangeToAnchor{*a, s.range_m}});
  // Every known anchor heard: no need to wait for the window.
  if (!done && group_.size() >= 3 && group_.size() >= anchors_.size()) done = flush_group();
  if (done) done->t = s.t;
  return done;
}

std::optional<PositionMeasurement> UwbFrontend::flush_group() {
  std::vector<RangeToAnchor> ranges;
  for (const auto& [id, r] : group_) ranges.push_back(r);
  group_.clear();
  const std::optional<Multilateration> m = multilaterate(ranges, z_B_, options_.multilateration);
  if (!m) return std::nullopt;
  ++stats_.fixes;
  return m->fix;
}

}  // namespace luxloc
