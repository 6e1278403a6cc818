#include "plugins/sim/sim_source.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
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
  o.sim.imu_rate_hz = spec.get_number("imu_rate", o.sim.imu_rate_hz);
  if (!(o.sim.imu_rate_hz >= 1.0 && o.sim.imu_rate_hz <= 10000.0))
    throw InputError("--source", 0, "imu_rate", "imu_rate must be 1..10000 Hz in " + spec.text);
  const double w = spec.get_number("width", 0.0), h = spec.get_number("height", 0.0);
  if ((w != 0.0 || h != 0.0) && !(w >= 16 && w <= 8192 && h >= 16 && h <= 8192 && w == std::floor(w) && h == std::floor(h)))
    throw InputError("--source", 0, "width", "width and height must be whole numbers of pixels 16..8192, both given, in " + spec.text);
  o.width = static_cast<int>(w);
  o.height = static_cast<int>(h);
  const std::string rt = spec.get("realtime", "1");
  if (rt != "0" && rt != "1") throw InputError("--source", 0, "realtime", "realtime must be 0 or 1 in " + spec.text);
  o.realtime = rt == "1";
  const std::string streams = spec.get("streams", "");
  if (!streams.empty()) {
    o.split = true;
    o.imu = o.frames = o.uwb = false;
    std::size_t start = 0;
    while (start <= streams.size()) {
      const std::size_t end = std::min(streams.find('+', start), streams.size());
      const std::string one = streams.substr(start, end - start);
      if (one == "imu")
        o.imu = true;
      else if (one == "frames")
        o.frames = true;
      else if (one == "uwb")
        o.uwb = true;
      else
        throw InputError("--source", 0, "streams",
                         "'" + spec.text + "': streams takes imu, frames, uwb or several joined by '+', got '" + one + "'");
      start = end + 1;
    }
  }
  o.faults = SimFaults::from_spec(spec);
  o.limits = spec.limits();
  return o;
}

// Split sim sources of one run share their t = 0: the first one to start sets it. Shared
// through a weak pointer, so the next run (the sources of this one gone) starts afresh.
class SimEpoch {
 public:
  TimeNs start() {
    TimeNs expected = -1;
    const TimeNs now = monotonic_now_ns();
    return t0_.compare_exchange_strong(expected, now) ? now : expected;
  }
  static std::shared_ptr<SimEpoch> shared() {
    static std::mutex m;
    static std::weak_ptr<SimEpoch> current;
    std::lock_guard lock(m);
    std::shared_ptr<SimEpoch> e = current.lock();
    if (!e) {
      e = std::make_shared<SimEpoch>();
      current = e;
    }
    return e;
  }

 private:
  std::atomic<TimeNs> t0_{-1};
};

namespace {

void set_time(SensorData& d, TimeNs t) {
  std::visit([t](auto& s) { s.t = t; }, d);
}

bool later(const auto& a, const auto& b) { return a.t > b.t; }

}  // namespace

sim::Scenario SimSourceOptions::scenario_with_camera() const {
  sim::Scenario sc = sim::make_scenario(scenario);
  if (width > 0 && height > 0) {
    CameraModel& c = sc.camera;
    const double scale = static_cast<double>(height) / c.height;
    c.fx *= scale;
    c.fy *= scale;
    c.width = width;
    c.height = height;
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
  }
  return sc;
}

SimSource::SimSource(SimSourceOptions options)
    : options_(std::move(options)),
      simulator_(options_.scenario_with_camera(), options_.sim),
      imu_(simulator_.imu_samples()),
      frames_(simulator_.scenario().frames && options_.frames ? simulator_.frame_count() : 0) {
  if (options_.uwb)
    for (const sim::SimUwbMeasurement& m : simulator_.uwb_measurements()) uwb_.push_back(m.sample);
  if (!options_.imu) imu_.clear();
  name_ = "sim:" + options_.scenario;
  if (options_.split) {
    std::string streams;
    for (const auto& [on, n] : {std::pair{options_.imu, "imu"}, {options_.frames, "frames"}, {options_.uwb, "uwb"}})
      if (on) streams += (streams.empty() ? "" : "+") + std::string(n);
    name_ += "/" + streams;
    epoch_ = SimEpoch::shared();
  }
}

std::string SimSource::failure() const { return failure_; }

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

bool SimSource::take(SensorData& out, TimeNs& t_sim) {
  constexpr TimeNs kNone = std::numeric_limits<TimeNs>::max();
  // The next sample in time order: IMU sample, frame (its time is its row 0's exposure
  // start, as in frames.csv) or UWB measurement.
  const TimeNs t_imu = next_imu_ < imu_.size() ? imu_[next_imu_].t : kNone;
  const TimeNs t_frame = next_frame_ < frames_ ? seconds_to_ns(simulator_.frame_time_s(next_frame_)) : kNone;
  const TimeNs t_uwb = next_uwb_ < uwb_.size() ? uwb_[next_uwb_].t : kNone;
  const TimeNs t = std::min({t_imu, t_frame, t_uwb});
  if (t == kNone) return false;
  t_sim = t;
  // The interval to this stream's next sample: a flood spreads its copies over it.
  TimeNs interval = 0;
  const bool stalled = options_.faults.stalled(ns_to_seconds(t));
  if (t == t_imu) {
    if (next_imu_ + 1 < imu_.size()) interval = imu_[next_imu_ + 1].t - t;
    out = imu_[next_imu_++];
  } else if (t == t_frame) {
    interval = seconds_to_ns(1.0 / options_.sim.fps);
    FrameSample f;
    f.t = t_frame;
    if (!stalled) f.gray = simulator_.render(next_frame_).gray;  // a stalled frame is never rendered
    ++next_frame_;
    out = std::move(f);
  } else {
    if (next_uwb_ + 1 < uwb_.size()) interval = uwb_[next_uwb_ + 1].t - t;
    out = uwb_[next_uwb_++];
  }
  if (!stalled && interval > 0 && options_.faults.flooding(ns_to_seconds(t)))
    for (int k = 1; k < kSimFloodFactor; ++k) {
      copies_.push_back({t + interval * k / kSimFloodFactor, out});
      std::push_heap(copies_.begin(), copies_.end(), [](const Copy& x, const Copy& y) { return later(x, y); });
    }
  return true;
}

bool SimSource::next(SensorData& out) {
  while (next_simulated(out))
    if (admit_plausible(out, options_.limits, drops(), name())) return true;
  return false;
}

bool SimSource::next_simulated(SensorData& out) {
  if (t0_ < 0) t0_ = epoch_ ? epoch_->start() : monotonic_now_ns();
  if (!failure_.empty()) return false;
  constexpr TimeNs kNone = std::numeric_limits<TimeNs>::max();
  const auto by_time = [](const Copy& a, const Copy& b) { return later(a, b); };
  for (;;) {
    // A flood's copies go out between the regular samples, in time order.
    TimeNs t_sim = 0;
    SensorData d;
    bool copy = false;
    if (!copies_.empty()) {
      const TimeNs t_imu = next_imu_ < imu_.size() ? imu_[next_imu_].t : kNone;
      const TimeNs t_frame = next_frame_ < frames_ ? seconds_to_ns(simulator_.frame_time_s(next_frame_)) : kNone;
      const TimeNs t_uwb = next_uwb_ < uwb_.size() ? uwb_[next_uwb_].t : kNone;
      if (copies_.front().t <= std::min({t_imu, t_frame, t_uwb})) {
        std::pop_heap(copies_.begin(), copies_.end(), by_time);
        t_sim = copies_.back().t;
        d = std::move(copies_.back().data);
        copies_.pop_back();
        copy = true;
      }
    }
    if (!copy && !take(d, t_sim)) return false;
    const double ts = ns_to_seconds(t_sim);
    if (options_.faults.dead(ts)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3f", *options_.faults.die_at_s);
      failure_ = name_ + ": fault injected: the source died at " + buf + " s";
      return false;
    }
    if (options_.faults.stalled(ts)) continue;  // lost, as a stalled device's samples are
    if (!wait_until(t0_ + t_sim + seconds_to_ns(options_.faults.lag_s))) return false;
    set_time(d, t0_ + t_sim + options_.faults.clock_error_ns(ts));
    out = std::move(d);
    return true;
  }
}

}  // namespace luxloc
