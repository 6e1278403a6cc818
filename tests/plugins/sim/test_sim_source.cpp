// The simulator as a live source: the same samples as the simulator, in time order, on the
// monotonic timeline; spec errors are input errors; request_stop ends a paced stream.
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "core/common/input_error.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/sim/sim_source.hpp"

using namespace luxloc;

TEST_CASE("sim: source emits the simulator's IMU and frames in time order", "[sim]") {
  SimSource src(SimSourceOptions::from_spec(SourceSpec::parse("sim:walk,duration=1,seed=3,realtime=0")));
  const std::vector<ImuSample> want = src.simulator().imu_samples();
  std::size_t imu = 0, frames = 0;
  TimeNs last = -1, t0 = -1;
  SensorData d;
  while (src.next(d)) {
    const TimeNs t = sample_time(d);
    CHECK(t >= last);
    last = t;
    if (const auto* s = std::get_if<ImuSample>(&d)) {
      if (t0 < 0) t0 = s->t - want[0].t;
      CHECK(s->t - t0 == want[imu].t);
      CHECK(s->acc_inB == want[imu].acc_inB);
      ++imu;
    } else {
      const auto& f = std::get<FrameSample>(d);
      CHECK(f.gray.cols == 640);
      ++frames;
    }
  }
  CHECK(imu == 100);
  CHECK(frames == 30);
  CHECK(src.live());
}

TEST_CASE("sim: a UWB scenario streams its UWB measurements and no frames, like luxloc sim writes it", "[sim]") {
  SimSource src(SimSourceOptions::from_spec(SourceSpec::parse("sim:uwb,duration=2,realtime=0")));
  const auto want = src.simulator().uwb_measurements();
  std::size_t imu = 0, uwb = 0, frames = 0;
  TimeNs last = -1;
  SensorData d;
  while (src.next(d)) {
    CHECK(sample_time(d) >= last);
    last = sample_time(d);
    imu += std::holds_alternative<ImuSample>(d);
    frames += std::holds_alternative<FrameSample>(d);
    if (const auto* u = std::get_if<UwbSample>(&d)) {
      CHECK(u->range_m == want[uwb].sample.range_m);
      ++uwb;
    }
  }
  CHECK(imu == 200);
  CHECK(frames == 0);
  CHECK(uwb == want.size());
  CHECK(uwb > 10);
}

TEST_CASE("sim: paced source stops on request, bad specs are input errors", "[sim]") {
  SimSource src(SimSourceOptions::from_spec(SourceSpec::parse("sim:static,duration=30")));
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    src.request_stop();
  });
  const auto start = std::chrono::steady_clock::now();
  SensorData d;
  int n = 0;
  while (src.next(d)) ++n;
  stopper.join();
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(took < 2.0);
  CHECK(n > 5);     // ~0.2 s of samples at 100 Hz + 30 fps
  CHECK(n < 200);   // paced, not the whole 30 s
  CHECK_THROWS_AS(SimSourceOptions::from_spec(SourceSpec::parse("sim:jog")), InputError);
  CHECK_THROWS_AS(SimSourceOptions::from_spec(SourceSpec::parse("sim:walk,seed=-1")), InputError);
  CHECK_THROWS_AS(SimSourceOptions::from_spec(SourceSpec::parse("sim:walk,realtime=yes")), InputError);
  CHECK_THROWS_AS(SimSourceOptions::from_spec(SourceSpec::parse("sim:walk,fps=0")), InputError);
  CHECK(make_live_source(SourceSpec::parse("sim:walk,duration=1"))->name() == "sim:walk");
}
