#include "calib/led_map_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/vlc/led_triangulation.hpp"

namespace luxloc {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Bearing rays towards each LED (by map index) from the sightings with a known pose.
std::map<int, std::vector<BearingRay>> rays_by_led(const CameraModel& camera, const std::vector<TimedLedSighting>& sightings,
                                                   const PoseLookup& pose_at) {
  std::map<int, std::vector<BearingRay>> rays;
  for (const TimedLedSighting& s : sightings) {
    const std::optional<DevicePose> pose = pose_at(s.t_obs);
    if (!pose) continue;
    const Eigen::Matrix3d R_BtoW = pose->q_BtoW.toRotationMatrix();
    BearingRay r;
    r.origin_inW = pose->p_BinW + R_BtoW * camera.p_CinB;
    r.dir_inW = (R_BtoW * camera.R_CtoB * camera.bearing(s.uv)).normalized();
    rays[s.led_index].push_back(r);
  }
  return rays;
}

}  // namespace

std::vector<TimedLedSighting> sightings_of_frame(TimeNs t_frame, const std::vector<LedObservation>& obs,
                                            const CameraModel& camera) {
  std::vector<TimedLedSighting> out;
  for (const LedObservation& o : obs) {
    if (!o.accepted()) continue;
    TimedLedSighting s;
    s.led_index = o.led_index;
    // Rolling shutter: the blob's rows were exposed row x row time after row 0.
    s.t_obs = t_frame + seconds_to_ns(camera.row_offset_s(o.uv.y()) + 0.5 * camera.exposure_s);
    s.uv = o.uv;
    s.freq_hz = o.freq_hz;
    s.freq_sigma_hz = o.period_rows > 0 ? o.freq_hz * o.period_sigma_rows / o.period_rows : 0.0;
    out.push_back(s);
  }
  return out;
}

void PoseTrack::add(TimeNs t, const DevicePose& p) {
  if (!t_.empty() && t <= t_.back()) return;  // keep strictly increasing
  t_.push_back(t);
  poses_.push_back(p);
}

std::optional<DevicePose> PoseTrack::at(TimeNs t) const {
  if (t_.empty() || t < t_.front() || t > t_.back()) return std::nullopt;
  const auto it = std::lower_bound(t_.begin(), t_.end(), t);
  const std::size_t k = static_cast<std::size_t>(it - t_.begin());
  if (*it == t) return poses_[k];
  const double a = static_cast<double>(t - t_[k - 1]) / static_cast<double>(t_[k] - t_[k - 1]);
  DevicePose p;
  p.p_BinW = (1 - a) * poses_[k - 1].p_BinW + a * poses_[k].p_BinW;
  p.q_BtoW = poses_[k - 1].q_BtoW.slerp(a, poses_[k].q_BtoW);
  return p;
}

LedRefineReport refine_led_map(const LedMap& map, const CameraModel& camera, const std::vector<TimedLedSighting>& sightings,
                               const PoseLookup& pose_at, const LedRefineOptions& options) {
  const auto rays = rays_by_led(camera, sightings, pose_at);
  std::vector<Led> leds = map.leds();
  LedRefineReport report;
  for (std::size_t i = 0; i < leds.size(); ++i) {
    LedRefinement r;
    r.id = leds[i].id;
    r.before = r.after = leds[i].p_inW;
    const auto it = rays.find(static_cast<int>(i));
    r.sightings = it == rays.end() ? 0 : it->second.size();
    if (r.sightings >= options.min_sightings) {
      TriangulationOptions t;
      t.huber_m = options.huber_m;
      if (options.fix_z) t.fixed_z = leds[i].p_inW.z();
      const TriangulatedPoint p = triangulate(it->second, t);
      if (p.ok) {
        r.refined = true;
        r.after = p.p_inW;
        r.rms_m = p.rms_m;
        leds[i].p_inW = p.p_inW;
      }
    }
    report.leds.push_back(r);
  }
  LedMapOptions relaxed;
  relaxed.min_relative_separation = 0.0;  // the frequencies are the input's: checked elsewhere
  report.map = LedMap(std::move(leds), "refined map", relaxed);
  return report;
}

LedCheckReport check_led_map(const LedMap& map, const CameraModel& camera, const std::vector<TimedLedSighting>& sightings,
                             const PoseLookup* pose_at, const LedCheckOptions& o) {
  LedCheckReport rep;
  const auto& leds = map.leds();
  std::vector<std::vector<double>> freqs(leds.size());
  std::vector<double> rel_sigmas;
  for (const TimedLedSighting& s : sightings) {
    if (s.led_index < 0 || static_cast<std::size_t>(s.led_index) >= leds.size()) continue;
    freqs[static_cast<std::size_t>(s.led_index)].push_back(s.freq_hz);
    if (s.freq_hz > 0) rel_sigmas.push_back(s.freq_sigma_hz / s.freq_hz);
  }
  // The decoder's frequency noise at this camera (row time, blob sizes): the spread of the
  // measured frequencies per LED, or the decoder's own sigma where an LED has few sightings.
  std::vector<double> spreads;
  for (std::size_t i = 0; i < leds.size(); ++i) {
    LedFrequencyStats f;
    f.id = leds[i].id;
    f.map_hz = leds[i].freq_hz;
    f.sightings = freqs[i].size();
    if (freqs[i].empty()) {
      rep.never_seen.push_back(leds[i].id);
    } else {
      double sum = 0, ss = 0;
      for (double v : freqs[i]) sum += v;
      f.mean_hz = sum / static_cast<double>(freqs[i].size());
      for (double v : freqs[i]) ss += (v - f.mean_hz) * (v - f.mean_hz);
      f.std_hz = freqs[i].size() > 1 ? std::sqrt(ss / static_cast<double>(freqs[i].size() - 1)) : 0.0;
      f.drifts = freqs[i].size() >= o.min_sightings &&
                 std::abs(f.mean_hz - f.map_hz) > o.drift_fraction * o.rel_tolerance * f.map_hz;
      if (freqs[i].size() >= o.min_sightings) spreads.push_back(f.std_hz / f.mean_hz);
    }
    rep.frequencies.push_back(f);
  }
  rep.relative_sigma = std::max(median(spreads), median(rel_sigmas));
  // Tolerance windows of +-3 sigma around two frequencies must not overlap.
  rep.needed_relative_spacing = std::max(o.min_relative_separation, 6.0 * rep.relative_sigma);
  for (std::size_t i = 0; i < leds.size(); ++i)
    for (std::size_t j = i + 1; j < leds.size(); ++j) {
      const double gap = std::abs(leds[i].freq_hz - leds[j].freq_hz);
      const double needed = rep.needed_relative_spacing * std::min(leds[i].freq_hz, leds[j].freq_hz);
      if (gap < needed) rep.collisions.push_back({leds[i].id, leds[j].id, gap, needed});
    }
  if (pose_at) {
    rep.checked_positions = true;
    LedRefineOptions ro;
    ro.min_sightings = o.min_sightings;
    const LedRefineReport refined = refine_led_map(map, camera, sightings, *pose_at, ro);
    for (const LedRefinement& r : refined.leds) {
      if (!r.refined) continue;
      const double d = (r.after - r.before).norm();
      if (d > o.position_threshold_m) rep.misplaced.push_back({r.id, d, r.after});
    }
  }
  return rep;
}

}  // namespace luxloc
