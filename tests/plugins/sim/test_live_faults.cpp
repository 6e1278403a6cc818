// Faults of live sources through the real pipeline (threads, queues, merge): a source that
// stalls, dies, floods at 10x or jumps its clock by +/-10 s (injected into the sim: source,
// plugins/sim/sim_faults.hpp), and a serial IMU (socat pty) that is unplugged and comes
// back. The run must go on with the other sources, the poses must say which source is
// missing, the source must resume, what is dropped must be counted by reason, and a clock
// jump must be re-based. Short faults here (each test a few seconds of real time); the 5 s
// stall with the real fusion is in tests/app/test_live_fault_run.cpp.
#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <thread>

#include "core/common/input_error.hpp"
#include "core/pipeline/pipeline.hpp"
#include "plugins/serial/serial_imu_source.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/sim/sim_source.hpp"
#include "../serial/socat_pair.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace std::chrono_literals;

namespace {

// A pose for every sample of source `driver` (the IMU, as the fusion does), mode "fused".
class PosePerSample final : public FusionStage {
 public:
  explicit PosePerSample(int driver) : driver_(driver) {}
  void process(const Sample& s, std::vector<PoseEstimate>& out) override {
    if (s.source != driver_) return;
    PoseEstimate p;
    p.t = s.t;
    p.mode = "fused";
    out.push_back(p);
  }

 private:
  int driver_;
};

struct Collected {
  std::mutex mutex;
  std::vector<PoseEstimate> poses;
};

class CollectingSink final : public PoseSink {
 public:
  explicit CollectingSink(Collected& c) : c_(c) {}
  std::string name() const override { return "collect"; }
  void write(const PoseEstimate& p) override {
    std::lock_guard lock(c_.mutex);
    c_.poses.push_back(p);
  }

 private:
  Collected& c_;
};

SourcePtr sim_source(const std::string& spec) {
  return std::make_unique<SimSource>(SimSourceOptions::from_spec(SourceSpec::parse(spec)));
}

PipelineReport run_live(std::vector<SourcePtr> sources, Collected& c, int driver = 0) {
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::make_unique<CollectingSink>(c));
  PipelineOptions o;
  o.live = true;
  Pipeline p(std::move(sources), std::move(sinks), o);
  PosePerSample stage(driver);
  return p.run(stage);
}

double max_gap_s(const std::vector<PoseEstimate>& poses) {
  double g = 0.0;
  for (std::size_t k = 1; k < poses.size(); ++k) g = std::max(g, ns_to_seconds(poses[k].t - poses[k - 1].t));
  return g;
}

std::uint64_t drops(const SourceReport& r) {
  std::uint64_t n = 0;
  for (const auto& [reason, e] : r.drops) n += e.count;
  return n;
}

}  // namespace

TEST_CASE("sim faults: spec parsing, and errors naming the key", "[sim]") {
  const SimSourceOptions o = SimSourceOptions::from_spec(
      SourceSpec::parse("sim:walk,streams=imu+uwb,die=7.5,stall=1:2/4:0.5,flood=3:1,jump=2:+10/5:-10"));
  CHECK(o.imu);
  CHECK_FALSE(o.frames);
  CHECK(o.uwb);
  REQUIRE(o.faults.die_at_s);
  CHECK(*o.faults.die_at_s == 7.5);
  REQUIRE(o.faults.stalls.size() == 2);
  CHECK(o.faults.stalled(2.9));
  CHECK_FALSE(o.faults.stalled(3.0));
  CHECK(o.faults.stalled(4.2));
  CHECK(o.faults.flooding(3.5));
  CHECK(o.faults.clock_error_ns(1.0) == 0);
  CHECK(o.faults.clock_error_ns(2.0) == 10 * kNsPerSecond);
  CHECK(o.faults.clock_error_ns(6.0) == 0);
  CHECK(SimSource(o).name() == "sim:walk/imu+uwb");
  CHECK(o.faults.lag_s == 0.0);
  CHECK(SimSourceOptions::from_spec(SourceSpec::parse("sim:walk,lag=0.12")).faults.lag_s == 0.12);
  for (const auto& [spec, key] : std::vector<std::pair<std::string, std::string>>{
           {"sim:walk,streams=imux", "streams"}, {"sim:walk,stall=1", "stall"}, {"sim:walk,stall=1:0", "stall"},
           {"sim:walk,flood=a:1", "flood"}, {"sim:walk,jump=-1:3", "jump"}, {"sim:walk,die=x", "die"},
           {"sim:walk,lag=-0.1", "lag"}, {"sim:walk,lag=120", "lag"}, {"sim:walk,lag=x", "lag"}}) {
    INFO(spec);
    try {
      (void)SimSourceOptions::from_spec(SourceSpec::parse(spec));
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.field() == key);
    }
  }
}

TEST_CASE("Live fault: a stalled source (1 s): the run goes on, the poses name it silent, it resumes", "[live-fault]") {
  std::vector<SourcePtr> s;
  s.push_back(sim_source("sim:walk,streams=imu,duration=3"));
  s.push_back(sim_source("sim:walk,streams=frames,duration=3,stall=1:1"));
  Collected c;
  const PipelineReport r = run_live(std::move(s), c);
  REQUIRE(c.poses.size() > 250);  // 100 Hz IMU over 3 s
  const TimeNs t0 = c.poses.front().t;
  CHECK(max_gap_s(c.poses) < 0.1);  // the IMU's poses never stopped
  int silent = 0, wrong = 0;
  for (const PoseEstimate& p : c.poses) {
    const double t = ns_to_seconds(p.t - t0);
    const bool marked = p.mode == "fused (sim:walk/frames silent)";
    if (marked) ++silent;
    if ((t < 1.0 || t > 2.1) && p.mode != "fused") ++wrong;  // before the stall and after it
    if (t > 1.6 && t < 1.95 && !marked) ++wrong;               // silent for longer than 0.5 s
  }
  CHECK(wrong == 0);
  CHECK(silent > 30);
  REQUIRE(r.sources.size() == 2);
  CHECK(r.sources[1].silences == 1);
  CHECK(r.sources[1].longest_silence_s == Approx(1.0).margin(0.1));
  CHECK(r.sources[1].samples > 50);  // about 60 frames less the 30 of the stall
  CHECK(r.sources[1].samples < 66);
  CHECK(r.sources[0].silences == 0);
  CHECK(r.sources[1].failure.empty());
}

TEST_CASE("Live fault: a source that dies: the rest goes on, the poses name it lost, its failure is reported", "[live-fault]") {
  std::vector<SourcePtr> s;
  s.push_back(sim_source("sim:walk,streams=imu,duration=2.5"));
  s.push_back(sim_source("sim:walk,streams=frames,duration=2.5,die=1"));
  Collected c;
  const PipelineReport r = run_live(std::move(s), c);
  REQUIRE(c.poses.size() > 200);
  const TimeNs t0 = c.poses.front().t;
  CHECK(ns_to_seconds(c.poses.back().t - t0) > 2.3);  // to the end of the IMU stream
  CHECK(max_gap_s(c.poses) < 0.1);
  int lost = 0;
  for (const PoseEstimate& p : c.poses)
    if (ns_to_seconds(p.t - t0) > 1.2) lost += p.mode == "fused (sim:walk/frames lost)";
  CHECK(lost > 100);
  CHECK(c.poses.front().mode == "fused");
  CHECK_THAT(r.sources[1].failure, Catch::Contains("sim:walk/frames") && Catch::Contains("died at 1.000 s"));
  CHECK(r.sources[0].failure.empty());
}

TEST_CASE("Live fault: a source flooding at 10x: the others lose nothing, all it sent is fused or counted", "[live-fault]") {
  std::vector<SourcePtr> s;
  s.push_back(sim_source("sim:walk,streams=imu,duration=2,flood=0.5:1"));
  s.push_back(sim_source("sim:walk,streams=frames,duration=2"));
  Collected c;
  const PipelineReport r = run_live(std::move(s), c);
  // 200 samples at 100 Hz, 9 more copies of each of the 100 in the flood window.
  CHECK(r.sources[0].samples + drops(r.sources[0]) == 200 + 9 * 100);
  CHECK(r.sources[0].samples > 1000);  // this host keeps up with 1 kHz
  CHECK(r.sources[1].samples + drops(r.sources[1]) == 60);
  CHECK(r.sources[1].drops.count("queue full") == 0);
  CHECK(r.sources[1].samples >= 57);
  CHECK(r.sources[1].silences == 0);
  CHECK(max_gap_s(c.poses) < 0.05);
}

TEST_CASE("Live fault: a clock jump of +10 s then -10 s is re-based, not fused as a gap nor dropped as late", "[live-fault]") {
  std::vector<SourcePtr> s;
  s.push_back(sim_source("sim:walk,streams=imu,duration=2.2,jump=0.7:+10/1.4:-10"));
  s.push_back(sim_source("sim:walk,streams=frames,duration=2.2"));
  Collected c;
  const PipelineReport r = run_live(std::move(s), c);
  REQUIRE(c.poses.size() > 180);
  CHECK(ns_to_seconds(c.poses.back().t - c.poses.front().t) < 2.5);  // not 12 s
  CHECK(max_gap_s(c.poses) < 0.1);
  CHECK(r.sources[0].clock_jumps == 2);
  CHECK(r.sources[0].first_clock_jump_s == Approx(10.0).margin(0.05));
  CHECK(r.sources[0].samples >= 215);  // of 220: at most a jittered sample at a jump is late
  CHECK(r.sources[1].drops.count("late (older than the reorder window)") <= 1);
  CHECK(r.sources[1].samples >= 60);
  CHECK(r.sources[1].clock_jumps == 0);
}

TEST_CASE("Live fault: a serial IMU unplugged for 1.5 s (pty, on_loss=wait) comes back, the run goes on", "[live-fault][imu]") {
  if (!test::SocatPair::available()) {
    WARN("socat not installed: serial pseudo-terminal test skipped");
    return;
  }
  test::SocatPair pty(test::scratch_dir("live_fault_serial"));
  REQUIRE(pty.running());
  SourceSpec spec = SourceSpec::parse("serial-imu:" + pty.b() + ",baud=115200,protocol=csv,columns=ax:ay:az:gx:gy:gz,on_loss=wait");
  SerialImuOptions io = SerialImuOptions::from_spec(spec);
  io.reopen_interval_s = 0.05;
  io.report_to_stderr = false;
  std::vector<SourcePtr> s;
  s.push_back(sim_source("sim:walk,streams=frames,duration=30"));  // drives the poses here; stopped below
  s.push_back(std::make_unique<SerialImuSource>(io));
  const std::string imu_name = s[1]->name();
  std::atomic<bool> stop{false};
  Collected c;
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::make_unique<CollectingSink>(c));
  PipelineOptions po;
  po.live = true;
  Pipeline pipeline(std::move(s), std::move(sinks), po);
  std::thread device([&] {
    const auto send = [&](int n) {
      SerialPort w(pty.a(), 115200);
      const std::string line = "0.01,0.02,9.81,0.001,0.002,0.003\n";
      for (int k = 0; k < n && !stop; ++k) {
        w.write_all(reinterpret_cast<const std::uint8_t*>(line.data()), line.size());
        std::this_thread::sleep_for(10ms);
      }
    };
    send(100);     // 1 s at 100 Hz
    pty.stop();    // unplugged
    std::this_thread::sleep_for(1500ms);
    pty.start();   // back, same path
    std::this_thread::sleep_for(100ms);
    send(100);
    std::this_thread::sleep_for(100ms);
    pipeline.stop();  // a live serial source never ends by itself
  });
  PosePerSample stage(0);
  const PipelineReport r = pipeline.run(stage);
  stop = true;
  device.join();
  REQUIRE(c.poses.size() > 100);
  int silent = 0;
  for (const PoseEstimate& p : c.poses) silent += p.mode == "fused (" + imu_name + " silent)";
  CHECK(silent > 20);  // > 1 s of 30 fps poses made while the IMU was away
  CHECK(c.poses.back().mode == "fused");  // and it came back
  const SourceReport& imu = r.sources[1];
  CHECK(imu.samples >= 180);
  CHECK(imu.drops.count("device lost") == 1);
  CHECK(imu.silences == 1);
  CHECK(imu.longest_silence_s > 1.0);
  CHECK(imu.failure.empty());
}
