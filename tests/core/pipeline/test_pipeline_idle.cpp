// The pipeline's threads sleep when their rings stay empty (core/pipeline/doorbell.hpp):
// an idle live run costs next to no CPU, and a sample after a silence still goes through
// at once (the sleeper is woken, not polled).
#include <catch2/catch.hpp>
#include <algorithm>
#include <condition_variable>
#include <ctime>
#include <mutex>
#include <thread>

#include "core/pipeline/pipeline.hpp"

using namespace luxloc;
using Clock = std::chrono::steady_clock;

namespace {

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// A live source that emits a fix every `gap` (none: silent) until stopped, and notes when
// it handed each one over.
class QuietSource : public Source {
 public:
  explicit QuietSource(std::chrono::milliseconds gap, int count) : gap_(gap), count_(count) {}
  std::string name() const override { return "quiet"; }
  bool live() const override { return true; }
  bool clock_follows_arrival() const override { return false; }
  bool next(SensorData& out) override {
    std::unique_lock lock(mutex_);
    if (emitted_ >= count_) {
      wake_.wait(lock, [&] { return stop_; });
      return false;
    }
    if (wake_.wait_for(lock, gap_, [&] { return stop_; })) return false;
    FixSample f;
    f.t = TimeNs{emitted_++} * 1'000'000;
    out = f;
    handed.push_back(Clock::now());
    return true;
  }
  void request_stop() override {
    std::lock_guard lock(mutex_);
    stop_ = true;
    wake_.notify_all();
  }
  std::vector<Clock::time_point> handed;  // read after the run

 private:
  std::chrono::milliseconds gap_;
  int count_;
  int emitted_ = 0;
  bool stop_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
};

struct EchoStage : FusionStage {
  void process(const Sample& s, std::vector<PoseEstimate>& out) override {
    PoseEstimate p;
    p.t = s.t;
    out.push_back(p);
  }
};

struct TimingSink : PoseSink {
  std::vector<Clock::time_point>* written;
  std::vector<double> latencies;
  explicit TimingSink(std::vector<Clock::time_point>* w) : written(w) {}
  std::string name() const override { return "timing"; }
  void write(const PoseEstimate& p) override {
    written->push_back(Clock::now());
    latencies.push_back(p.latency_s);
  }
};

}  // namespace

TEST_CASE("An idle live pipeline sleeps instead of polling", "[pipeline]") {
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<QuietSource>(std::chrono::milliseconds(1), 1));  // one sample, then silence
  std::vector<Clock::time_point> written;
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::make_unique<TimingSink>(&written));
  PipelineOptions o;
  o.live = true;
  Pipeline p(std::move(sources), std::move(sinks), o);
  EchoStage stage;
  double cpu_s = 0.0;
  std::thread meter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const double c0 = process_cpu_s();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    cpu_s = process_cpu_s() - c0;
    p.stop();
    p.sources().front()->request_stop();
  });
  p.run(stage);
  meter.join();
  CHECK(written.size() == 1);
  // The spin/yield/50 us-sleep loop this replaced used 20-35 % of a core here; asleep, the
  // threads wake about 10 times a second (the bound that lets them see a stop flag).
  INFO("CPU over 1.5 s idle: " << cpu_s << " s");
  CHECK(cpu_s < 0.03);
}

TEST_CASE("A sample after a silence wakes the sleeping pipeline at once", "[pipeline]") {
  auto source = std::make_unique<QuietSource>(std::chrono::milliseconds(250), 6);
  QuietSource* src = source.get();
  std::vector<SourcePtr> sources;
  sources.push_back(std::move(source));
  std::vector<Clock::time_point> written;
  std::vector<PoseSinkPtr> sinks;
  auto timing = std::make_unique<TimingSink>(&written);
  const TimingSink* sink = timing.get();
  sinks.push_back(std::move(timing));
  PipelineOptions o;
  o.live = true;
  Pipeline p(std::move(sources), std::move(sinks), o);
  EchoStage stage;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(6 * 250 + 300));
    p.stop();
    src->request_stop();
  });
  const PipelineReport report = p.run(stage);
  stopper.join();
  REQUIRE(written.size() == 6);
  // Every pose carries its input's age, and the run sums them up.
  for (const double l : sink->latencies) {
    CHECK(l >= 0.0);
    CHECK(l < 1.0);
  }
  CHECK(report.latency.count == 6);
  CHECK(report.paced);
  CHECK(report.latency.max_s >= report.latency.p50_s);
  REQUIRE(src->handed.size() == 6);
  // Each followed a 250 ms silence; its pose was written within a few ms, not at the next
  // 100 ms poll. (At most one may be late on a loaded machine.)
  int prompt = 0;
  for (std::size_t i = 0; i < written.size(); ++i) {
    const double ms = std::chrono::duration<double, std::milli>(written[i] - src->handed[i]).count();
    INFO("sample " << i << ": " << ms << " ms");
    if (ms < 20.0) ++prompt;
  }
  CHECK(prompt >= 5);
}
