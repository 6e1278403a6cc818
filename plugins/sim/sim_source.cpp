#include "plugins/sim/sim_source.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "core/common/input_error.hpp"
#include "core/sim/scenario.hpp"
#include "plugins/serial/monotonic_clock.hpp"

namespace luxloc {

SimSourceOptions SimSourceOptions::from_spec(const SourceSpec& spec) {
  SimSourceOptions o;
  o.scenario = spec.target.empty() ? "walk" : spec.target;
  const auto names = sim::scenario_names();
  if (std::find(names.begin(), names.end(), o.scenario) == names.end()) {
    std::string all;
    for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
    throw InputError("--source", 0, spec.text, "unknown scenario '" + o.scenario + "' (known: " + all + ")");
  }
  const double seed = spec.get_number("seed", 1.0);
  if (seed < 0 || seed != static_cast<double>(static_cast<std::uint64_t>(seed)))
    throw InputError("--source", 0, "seed", "seed must be a whole number >= 0 in " + spec.text);
  o.sim.seed = static_cast<std::uint64_t>(seed);
  o.sim.duration_s = spec.get_number("duration", 0.0);
  o.sim.fps = spec.get_number("fps", o.sim.fps);
  if (o.sim.duration_s < 0.0 || !(o.sim.fps > 0.0))
    throw InputError("--source", 0, "duration", "duration must be >= 0 and fps > 0 in " + spec.text);
  const std::string rt = spec.get("realtime", "1");
  if (rt != "0" && rt != "1") throw InputError("--source", 0, "realtime", "realtime must be 0 or 1 in " + spec.text);
  o.realtime = rt == "1";
  o.limits = spec.limits();
  return o;
}

SimSource::SimSource(SimSourceOptions options)
    : options_(std::move(options)),
      simulator_(sim::make_scenario(options_.scenario), options_.sim),
      imu_(simulator_.imu_samples()),
      frames_(simulator_.scenario().frames ? simulator_.frame_count() : 0) {
  for (const sim::SimUwbMeasurement& m : simulator_.uwb_measurements()) uwb_.push_back(m.sample);
}

void SimSource::request_stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
}

bool SimSource::wait_until(TimeNs t) {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (stop_) return false;
    const TimeNs now = monotonic_now_ns();
    if (!options_.realtime || now >= t) return true;
    wake_.wait_for(lock, std::chrono::nanoseconds(t - now));
  }
}

bool SimSource::next(SensorData& out) {
  while (next_simulated(out))
    if (admit_plausible(out, options_.limits, drops(), name())) return true;
  return false;
}

bool SimSource::next_simulated(SensorData& out) {
  if (t0_ < 0) t0_ = monotonic_now_ns();
  constexpr TimeNs kNone = std::numeric_limits<TimeNs>::max();
  // The next sample in time order: IMU sample, frame (its time is its row 0's exposure
  // start, as in frames.csv) or UWB measurement.
  const TimeNs t_imu = next_imu_ < imu_.size() ? imu_[next_imu_].t : kNone;
  const TimeNs t_frame = next_frame_ < frames_ ? seconds_to_ns(simulator_.frame_time_s(next_frame_)) : kNone;
  const TimeNs t_uwb = next_uwb_ < uwb_.size() ? uwb_[next_uwb_].t : kNone;
  const TimeNs t = std::min({t_imu, t_frame, t_uwb});
  if (t == kNone || !wait_until(t0_ + t)) return false;
  if (t == t_imu) {
    ImuSample s = imu_[next_imu_++];
    s.t += t0_;
    out = std::move(s);
  } else if (t == t_frame) {
    FrameSample f;
    f.t = t0_ + t_frame;
    f.gray = simulator_.render(next_frame_++).gray;
    out = std::move(f);
  } else {
    UwbSample u = uwb_[next_uwb_++];
    u.t += t0_;
    out = std::move(u);
  }
  return true;
}

}  // namespace luxloc
