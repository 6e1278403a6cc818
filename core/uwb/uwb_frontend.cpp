#include "core/uwb/uwb_frontend.hpp"

#include <algorithm>
#include <cmath>

#include "core/uwb/tof_aoa_fix.hpp"

namespace luxloc {
namespace {

// Resolves UwbOnline::automatic from the configured anchors. Biases: >= 4 anchors (one range
// more than a 3-D fix needs, so a bias shows as a residual); height: >= 4 anchors, some
// >= 0.5 m below and some >= 0.5 m above the nominal height (ranges to a low and a high
// anchor move opposite ways with z, which separates z from the biases; with all anchors on
// one side z trades against a common bias: on the sim robot, anchors 0-2 m above a 0.5 m
// device, estimating z made the ATE worse, 0.089 vs 0.081 m on seeds 1-10). A one-station
// or ceiling-only layout keeps the nominal height, the planar pedestrian case as before.
// Never in --uwb-alone (the plain baseline).
HeightBiasOptions resolve_online(const UwbOptions& o, const UwbAnchorTable& anchors, double z_B) {
  HeightBiasOptions h = o.online;
  const bool many = anchors.size() >= 4;
  bool below = false, above = false;
  for (const auto& [id, p] : anchors.positions()) {
    below = below || p.z() <= z_B - 0.5;
    above = above || p.z() >= z_B + 0.5;
  }
  const bool spread = many && below && above;
  h.estimate_bias = !o.fixes_only && (o.bias == UwbOnline::on || (o.bias == UwbOnline::automatic && many));
  h.estimate_height = !o.fixes_only && (o.height == UwbOnline::on || (o.height == UwbOnline::automatic && spread));
  h.estimate_scale = h.estimate_bias && o.scale == UwbOnline::on;  // automatic: off (UwbOptions::scale)
  return h;
}

}  // namespace

UwbFrontend::UwbFrontend(const UwbOptions& options, UwbAnchorTable anchors, double z_B)
    : options_(options), anchors_(std::move(anchors)), height_bias_(resolve_online(options_, anchors_, z_B), z_B) {
  options_.multilateration.range_sigma_m = options_.noise.range_sigma_m;
  for (const auto& [id, p] : anchors_.positions()) height_bias_.add_anchor(id, anchors_.calibrated(id));
}

void UwbFrontend::summarize_online() {
  const HeightBiasStats& h = height_bias_.stats();
  stats_.online_used = h.used;
  stats_.online_gated_long = h.gated_long;
  stats_.online_gated_short = h.gated_short;
  stats_.online_bias_reopened = h.bias_reopened;
  if (height_bias_.options().estimate_height) {
    stats_.final_height_m = height_bias_.height_m();
    stats_.final_height_sigma_m = height_bias_.height_sigma_m();
  }
  stats_.learnt_bias_m.clear();
  stats_.learnt_scale.clear();
  if (height_bias_.options().estimate_bias)
    for (const auto& [id, p] : anchors_.positions()) {
      stats_.learnt_bias_m.emplace_back(id, height_bias_.bias_m(id));
      if (height_bias_.options().estimate_scale) stats_.learnt_scale.emplace_back(id, height_bias_.scale(id));
    }
}

bool UwbFrontend::nlos(int anchor) const {
  if (!height_bias_.nlos(anchor)) return false;
  std::size_t flagged = 0;
  for (const auto& [id, p] : anchors_.positions()) flagged += height_bias_.nlos(id);
  return 3 * flagged <= anchors_.size();
}

double UwbFrontend::corrected_range(const UwbSample& s) const {
  return height_bias_.corrected(s.anchor, anchors_.corrected_range(s.anchor, s.range_m));
}

void UwbFrontend::observe(const UwbSample& s, const PlanarEstimate& e) {
  if (!height_bias_.enabled() || !e.valid || std::isfinite(s.aoa_rad)) return;
  const std::optional<Eigen::Vector3d> a = anchors_.find(s.anchor);
  if (!a || !std::isfinite(s.range_m)) return;
  height_bias_.add_anchor(s.anchor, anchors_.calibrated(s.anchor));  // a learnt anchor
  height_bias_.start(s.t, e.p, e.cov_p);  // the first planar estimate only: then ranges alone
  height_bias_.predict(s.t);
  height_bias_.update(s.anchor, *a, anchors_.corrected_range(s.anchor, s.range_m), options_.noise.range_sigma_m);
}

HeightBiasFilter::Outcome UwbFrontend::observe_height(TimeNs t, double z_m, double sigma_m) {
  if (!height_bias_.started()) return HeightBiasFilter::Outcome::skipped;
  height_bias_.predict(t);
  return height_bias_.update_height(z_m, sigma_m);
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
  // The learnt states' own uncertainty widens the LOS core (two-sided around the learnt
  // bias, part 2): sigma^2 + sigma_b^2 + (d sigma_s)^2 + (dz / d)^2 sigma_z^2, dz / d at the
  // range itself (sigma_s: the scale's, which grows with the distance).
  UwbNoiseModel noise = options_.noise;
  const double range = corrected_range(s);
  if (height_bias_.enabled()) {
    const double dz = height_bias_.height_m() - a->z();
    const double slope = std::min(1.0, std::abs(dz) / std::max(range, 0.1));
    const double sb = height_bias_.bias_sigma_m(s.anchor), sz = slope * height_bias_.height_sigma_m();
    const double ss = range * height_bias_.scale_sigma(s.anchor);
    noise.range_sigma_m = std::sqrt(noise.range_sigma_m * noise.range_sigma_m + sb * sb + ss * ss + sz * sz);
  }
  return UwbRangeLikelihood(*a, height_bias_.height_m(), range, s.aoa_rad, noise);
}

std::optional<PositionMeasurement> UwbFrontend::fix(const UwbSample& measured) {
  UwbSample s = measured;
  s.range_m = corrected_range(measured);
  const std::optional<Eigen::Vector3d> a = anchors_.find(s.anchor);
  if (!a || !std::isfinite(s.range_m) || s.range_m < 0.0) return std::nullopt;
  if (std::isfinite(s.aoa_rad)) {
    last_fix_outside_hull_ = false;
    std::optional<PositionMeasurement> m = tof_aoa_fix(s, *a, height_bias_.height_m(), options_.noise);
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
  std::vector<Eigen::Vector2d> area;  // every known anchor: the room the fix should lie in
  for (const auto& [id, p] : anchors_.positions()) area.push_back(p.head<2>());
  const std::optional<Multilateration> m = multilaterate(ranges, height_bias_.height_m(), options_.multilateration, area);
  if (!m) return std::nullopt;
  ++stats_.fixes;
  last_fix_outside_hull_ = m->outside_hull;
  if (m->outside_hull) ++stats_.fixes_outside_hull;
  return m->fix;
}

}  // namespace luxloc
