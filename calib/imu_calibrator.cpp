#include "calib/imu_calibrator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace luxloc::calib {

ImuCalibrationInfo ImuCalibrationResult::info() const {
  ImuCalibrationInfo i;
  i.method = orientations.empty() ? "static" : "six-position";
  if (!orientations.empty()) i.acc_residual_rms_mps2 = accel.residual_rms_mps2;
  i.static_segments = static_cast<int>(segments.size());
  i.static_seconds = static_seconds;
  return i;
}

std::vector<StaticSegment> find_static_segments(const std::vector<ImuSample>& samples, const StillOptions& still,
                                                double min_segment_s) {
  // Pass 1: mark still samples. The detector flags the newest sample of a quiet window, so
  // the whole window is still too: mark it backwards.
  StillDetector detector(still);
  std::vector<char> is_still(samples.size(), 0);
  const TimeNs window = seconds_to_ns(still.window_s);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!detector.update(samples[i])) continue;
    for (std::size_t j = i + 1; j-- > 0 && samples[i].t - samples[j].t <= window && !is_still[j];) is_still[j] = 1;
    is_still[i] = 1;
  }
  // Pass 2: runs of still samples, trimmed by half a window at each end.
  std::vector<StaticSegment> out;
  const TimeNs trim = window / 2;
  for (std::size_t i = 0; i < samples.size();) {
    if (!is_still[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < samples.size() && is_still[j]) ++j;
    const TimeNs t0 = samples[i].t + trim, t1 = samples[j - 1].t - trim;
    if (ns_to_seconds(t1 - t0) >= min_segment_s) {
      StaticSegment s;
      s.t0 = t0;
      s.t1 = t1;
      for (std::size_t k = i; k < j; ++k) {
        if (samples[k].t < t0 || samples[k].t > t1) continue;
        s.mean_acc += samples[k].acc_inB;
        s.mean_gyro += samples[k].gyro_inB;
        ++s.samples;
      }
      if (s.samples > 0) {
        s.mean_acc /= static_cast<double>(s.samples);
        s.mean_gyro /= static_cast<double>(s.samples);
        out.push_back(s);
      }
    }
    i = j;
  }
  return out;
}

ImuCalibrationResult calibrate_imu(const std::vector<ImuSample>& samples, const ImuCalibratorOptions& options) {
  ImuCalibrationResult r;
  r.segments = find_static_segments(samples, options.still, options.min_segment_s);
  if (r.segments.empty())
    throw std::invalid_argument("no static segment of at least " + std::to_string(options.min_segment_s) +
                                " s: hold the IMU still (on a table) while recording");

  // Gyro bias: all static samples weigh the same.
  std::size_t n = 0;
  for (const StaticSegment& s : r.segments) {
    r.calibration.gyro_bias += s.mean_gyro * static_cast<double>(s.samples);
    n += s.samples;
    r.static_seconds += ns_to_seconds(s.t1 - s.t0);
  }
  r.calibration.gyro_bias /= static_cast<double>(n);
  if (options.mode == ImuCalibMode::static_only) return r;

  // Group segments by gravity direction; each group's sample-weighted mean is one orientation.
  std::vector<Eigen::Vector3d> sums;
  std::vector<std::size_t> counts;
  for (StaticSegment& s : r.segments) {
    const Eigen::Vector3d dir = s.mean_acc.normalized();
    int found = -1;
    for (std::size_t k = 0; k < sums.size() && found < 0; ++k)
      if (std::acos(std::clamp(dir.dot(sums[k].normalized()), -1.0, 1.0)) < options.orientation_merge_rad)
        found = static_cast<int>(k);
    if (found < 0) {
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
      found = static_cast<int>(sums.size()) - 1;
    }
    sums[found] += s.mean_acc * static_cast<double>(s.samples);
    counts[found] += s.samples;
    s.orientation = found;
  }
  for (std::size_t k = 0; k < sums.size(); ++k) r.orientations.push_back(sums[k] / static_cast<double>(counts[k]));
  if (r.orientations.size() < 6) {
    std::string seen;
    for (const Eigen::Vector3d& o : r.orientations) seen += std::string(seen.empty() ? "" : " ") + up_axis_name(o);
    throw std::invalid_argument("found " + std::to_string(r.orientations.size()) +
                                " static orientation(s) (" + seen +
                                " up), six-position calibration needs 6: each of +x -x +y -y +z -z up, " +
                                std::to_string(options.min_segment_s) + " s or more each");
  }
  r.accel = solve_accel_calibration(r.orientations, options.gravity);
  r.calibration.acc_bias = r.accel.bias;
  r.calibration.acc_scale = r.accel.scale;
  return r;
}

}  // namespace luxloc::calib
