#pragma once
// `sim:SCENARIO[,seed=..,duration=..,fps=..,imu_rate=..,width=..,height=..,realtime=1|0,streams=..,FAULTS]`: the simulator (core/sim) as a
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
//
// streams=imu|frames|uwb (or several joined by '+'): only those streams, so one scenario
// can feed a run as separate sources (named sim:SCENARIO/STREAMS), each of which can fail
// on its own; such split sources share t = 0 (the first to start sets it), i.e. one
// timeline. Faults (die, stall, flood, jump: plugins/sim/sim_faults.hpp) are injected per
// source.
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "core/pipeline/source.hpp"
#include "core/sim/simulator.hpp"
#include "plugins/sim/sim_faults.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

struct SimSourceOptions {
  std::string scenario = "walk";
  sim::SimOptions sim;
  bool realtime = true;
  bool imu = true, frames = true, uwb = true;  // streams=
  bool split = false;                          // streams= given: a share of the scenario
  SimFaults faults;
  SensorLimits limits;  // the simulator's samples pass the same edge check as a device's
  int width = 0, height = 0;  // width=, height=: the camera's image size (0: the scenario's)

  // The scenario with the camera resized (width=, height=): square pixels, the focal
  // length scaled with the height (the vertical field of view kept), centred principal
  // point. The run's camera (live_session_defaults) and the rendered frames both use it.
  sim::Scenario scenario_with_camera() const;

  // From a parsed --source spec; throws InputError (field = the key) for bad values.
  static SimSourceOptions from_spec(const SourceSpec& spec);
};

class SimSource final : public Source {
 public:
  explicit SimSource(SimSourceOptions options);
  std::string name() const override { return name_; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  // In real time the stamps follow the arrival clock (the pipeline re-bases a jump);
  // realtime=0 runs ahead of it by design.
  bool clock_follows_arrival() const override { return options_.realtime; }
  std::string failure() const override;
  const sim::Simulator& simulator() const { return simulator_; }

 private:
  // Sleeps until `t` (on the monotonic clock) or a stop; false when stopped.
  bool wait_until(TimeNs t);
  // The next sample of the scenario in time order (simulated time), false at the end.
  bool take(SensorData& out, TimeNs& t_sim);
  // The next sample (faults applied), before the plausibility check.
  bool next_simulated(SensorData& out);

  struct Copy {  // a flood's extra copy of a sample, due at simulated time t
    TimeNs t;
    SensorData data;
  };

  SimSourceOptions options_;
  sim::Simulator simulator_;
  std::vector<ImuSample> imu_;
  std::vector<UwbSample> uwb_;
  std::size_t frames_ = 0;  // 0 when the scenario has no camera
  std::size_t next_imu_ = 0, next_frame_ = 0, next_uwb_ = 0;
  TimeNs t0_ = -1;  // monotonic time of simulated t = 0, set at the first next()
  std::string name_;
  std::shared_ptr<class SimEpoch> epoch_;  // split sources: t0 shared
  std::vector<Copy> copies_;               // min-heap on t
  std::string failure_;                    // written and read on the source thread
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stop_{false};
};

}  // namespace luxloc
