#pragma once
// `sim:SCENARIO[,seed=..,duration=..,fps=..,realtime=1|0]`: the simulator (core/sim) as a
// live source — one stream of what `luxloc sim` would write for the scenario (IMU samples,
// camera frames where the scenario has a camera, UWB measurements where it has anchors), in
// time order, each
// emitted when the wall clock reaches it (realtime=0: as fast as the consumer takes them).
// Demos and tests of the live path without hardware: `luxloc run --source sim:walk`,
// `luxloc record --source sim:walk --out DIR`.
//
// Timestamps are CLOCK_MONOTONIC ns at the start of the run plus the simulated time, the
// timeline every live source shares. The scenario's LED map, camera and device height are
// what the run uses unless --map / --camera say otherwise, and its UWB anchors
// (live_session_defaults()).
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "core/pipeline/source.hpp"
#include "core/sim/simulator.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

struct SimSourceOptions {
  std::string scenario = "walk";
  sim::SimOptions sim;
  bool realtime = true;
  SensorLimits limits;  // the simulator's samples pass the same edge check as a device's

  // From a parsed --source spec; throws InputError (field = the key) for bad values.
  static SimSourceOptions from_spec(const SourceSpec& spec);
};

class SimSource final : public Source {
 public:
  explicit SimSource(SimSourceOptions options);
  std::string name() const override { return "sim:" + options_.scenario; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  const sim::Simulator& simulator() const { return simulator_; }

 private:
  // Sleeps until `t` (on the monotonic clock) or a stop; false when stopped.
  bool wait_until(TimeNs t);
  // The next simulated sample, before the plausibility check.
  bool next_simulated(SensorData& out);

  SimSourceOptions options_;
  sim::Simulator simulator_;
  std::vector<ImuSample> imu_;
  std::vector<UwbSample> uwb_;
  std::size_t frames_ = 0;  // 0 when the scenario has no camera
  std::size_t next_imu_ = 0, next_frame_ = 0, next_uwb_ = 0;
  TimeNs t0_ = -1;  // monotonic time of simulated t = 0, set at the first next()
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stop_{false};
};

}  // namespace luxloc
