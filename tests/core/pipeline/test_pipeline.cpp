#include <catch2/catch.hpp>
#include <atomic>
#include <thread>

#include "core/pipeline/pipeline.hpp"

using namespace luxloc;

namespace {

// A playback-like source emitting FixSamples at given times (ms), optionally slowly.
class ListSource : public Source {
 public:
  ListSource(std::string name, std::vector<int> times_ms, int delay_us = 0)
      : name_(std::move(name)), times_(std::move(times_ms)), delay_us_(delay_us) {}
  std::string name() const override { return name_; }
  bool next(SensorData& out) override {
    if (i_ >= times_.size()) return false;
    if (delay_us_) std::this_thread::sleep_for(std::chrono::microseconds(delay_us_));
    FixSample f;
    f.t = TimeNs{times_[i_++]} * 1'000'000;
    out = f;
    return true;
  }

 private:
  std::string name_;
  std::vector<int> times_;
  int delay_us_;
  std::size_t i_ = 0;
};

struct Recorder : FusionStage {
  std::vector<std::pair<TimeNs, int>> seen;
  void process(const Sample& s, std::vector<PoseEstimate>& out) override {
    seen.emplace_back(s.t, s.source);
    PoseEstimate p;
    p.t = s.t;
    out.push_back(p);
  }
};

struct CollectSink : PoseSink {
  std::vector<TimeNs>* times;
  explicit CollectSink(std::vector<TimeNs>* t) : times(t) {}
  std::string name() const override { return "collect"; }
  void write(const PoseEstimate& p) override { times->push_back(p.t); }
};

}  // namespace

TEST_CASE("Pipeline merges playback sources in exact timestamp order", "[pipeline]") {
  std::vector<int> a, b, c;
  for (int i = 0; i < 3000; ++i) a.push_back(i * 10);        // 100 Hz
  for (int i = 0; i < 900; ++i) b.push_back(i * 33 + 5);     // 30 Hz, slow producer
  for (int i = 0; i < 30; ++i) c.push_back(i * 1000 + 7);    // 1 Hz
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<ListSource>("a", a));
  sources.push_back(std::make_unique<ListSource>("b", b, 20));
  sources.push_back(std::make_unique<ListSource>("c", c));
  std::vector<TimeNs> written;
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::make_unique<CollectSink>(&written));
  PipelineOptions opt;
  opt.source_queue_capacity = 8;  // force backpressure
  Pipeline p(std::move(sources), std::move(sinks), opt);
  Recorder rec;
  const PipelineReport r = p.run(rec);
  REQUIRE(rec.seen.size() == a.size() + b.size() + c.size());
  for (std::size_t i = 1; i < rec.seen.size(); ++i) REQUIRE(rec.seen[i - 1].first <= rec.seen[i].first);
  REQUIRE(written.size() == rec.seen.size());  // every pose reached the sink
  REQUIRE(r.poses == rec.seen.size());
  REQUIRE(r.sources.size() == 3);
  REQUIRE(r.sources[1].samples == b.size());
  REQUIRE(r.data_span_s() == Approx(29.99));
}

TEST_CASE("Pipeline applies per-source clock offsets", "[pipeline]") {
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<ListSource>("imu", std::vector<int>{0, 10, 20, 30}));
  sources.push_back(std::make_unique<ListSource>("cam", std::vector<int>{0, 10}));
  PipelineOptions opt;
  opt.clock_offsets_ns = {0, 15'000'000};  // camera clock 15 ms behind
  Pipeline p(std::move(sources), {}, opt);
  Recorder rec;
  p.run(rec);
  std::vector<std::pair<TimeNs, int>> expect = {{0, 0}, {10'000'000, 0}, {15'000'000, 1},
                                                {20'000'000, 0}, {25'000'000, 1}, {30'000'000, 0}};
  REQUIRE(rec.seen == expect);
}

TEST_CASE("Live pipeline drops samples older than what was fused, and counts them", "[pipeline]") {
  // Source b delivers its samples late (wall clock) with old timestamps: after the reorder
  // window the merger moves on, and b's stale samples are dropped as late.
  std::vector<SourcePtr> sources;
  std::vector<int> a;
  for (int i = 0; i < 50; ++i) a.push_back(100 + i);
  sources.push_back(std::make_unique<ListSource>("a", a));
  sources.push_back(std::make_unique<ListSource>("b", std::vector<int>{1, 2, 3}, 150'000));
  PipelineOptions opt;
  opt.live = true;
  opt.reorder_window = std::chrono::milliseconds(20);
  Pipeline p(std::move(sources), {}, opt);
  Recorder rec;
  const PipelineReport r = p.run(rec);
  REQUIRE(r.sources[1].drops.count("late (older than the reorder window)") == 1);
  REQUIRE(r.sources[1].drops.at("late (older than the reorder window)").count == 3);
  REQUIRE(rec.seen.size() == 50);
  for (std::size_t i = 1; i < rec.seen.size(); ++i) REQUIRE(rec.seen[i - 1].first <= rec.seen[i].first);
}

TEST_CASE("Pipeline stop() ends the run and still delivers every computed pose", "[pipeline]") {
  std::vector<int> a;
  for (int i = 0; i < 100000; ++i) a.push_back(i);
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<ListSource>("a", a, 5));
  std::vector<TimeNs> written;
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::make_unique<CollectSink>(&written));
  Pipeline p(std::move(sources), std::move(sinks), PipelineOptions{});
  Recorder rec;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    p.stop();
  });
  const PipelineReport r = p.run(rec);
  stopper.join();
  REQUIRE(r.stopped);
  REQUIRE(rec.seen.size() > 0);
  REQUIRE(rec.seen.size() < a.size());
  REQUIRE(written.size() == rec.seen.size());
}

namespace {

// Emits `count` 1 MiB frames as fast as the queue takes them and counts what it produced.
class BigFrameSource : public Source {
 public:
  BigFrameSource(int count, std::atomic<int>& produced) : count_(count), produced_(produced) {}
  std::string name() const override { return "frames"; }
  bool next(SensorData& out) override {
    if (i_ >= count_) return false;
    FrameSample f;
    f.t = TimeNs{i_++} * 33'000'000;
    f.gray = cv::Mat(1024, 1024, CV_8UC1, cv::Scalar(0));
    out = std::move(f);
    produced_.fetch_add(1);
    return true;
  }

 private:
  int count_, i_ = 0;
  std::atomic<int>& produced_;
};

// A slow fusion stage that notes how far ahead of it the source got.
struct SlowStage : FusionStage {
  std::atomic<int>* produced = nullptr;
  int fused = 0, most_ahead = 0;
  void process(const Sample&, std::vector<PoseEstimate>&) override {
    // At the first sample, wait until the source has stopped producing (blocked by the
    // budget, or done): how far ahead it gets must not depend on how fast this machine
    // (or TSan, or a loaded CI box) lets it run. A per-sample sleep alone did not: on a
    // loaded TSan run the source was only 1 frame ahead.
    if (fused == 0) wait_for_source_stall();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ++fused;
    most_ahead = std::max(most_ahead, produced->load() - fused);
  }
  // Stalled: no new frame for 500 ms (20 s at most, so a broken budget cannot hang the test).
  void wait_for_source_stall() const {
    int last = produced->load(), still_ms = 0;
    for (int waited_ms = 0; still_ms < 500 && waited_ms < 20'000; waited_ms += 10) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      const int now = produced->load();
      still_ms = now == last ? still_ms + 10 : 0;
      last = now;
    }
  }
};

}  // namespace

TEST_CASE("Pipeline bounds the frame memory queued per source (source_queue_bytes)", "[pipeline]") {
  // 1 MiB frames against a 4 MiB budget: the source can be at most 4 queued + 1 being
  // pushed ahead of the fusion, however many slots the queue has (256).
  std::atomic<int> produced{0};
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<BigFrameSource>(40, produced));
  PipelineOptions opt;
  opt.source_queue_bytes = std::size_t{4} << 20;
  Pipeline p(std::move(sources), {}, opt);
  SlowStage stage;
  stage.produced = &produced;
  const PipelineReport r = p.run(stage);
  CHECK(stage.fused == 40);  // playback: waits, loses nothing
  CHECK(r.sources[0].samples == 40);
  CHECK(stage.most_ahead <= 5);
  CHECK(stage.most_ahead >= 3);  // the budget, not something smaller, is what held it

  SECTION("live: beyond the budget, frames are dropped as queue full") {
    std::atomic<int> live_produced{0};
    std::vector<SourcePtr> live;
    live.push_back(std::make_unique<BigFrameSource>(40, live_produced));
    opt.live = true;
    Pipeline lp(std::move(live), {}, opt);
    SlowStage s2;
    s2.produced = &live_produced;
    const PipelineReport lr = lp.run(s2);
    REQUIRE(lr.sources[0].drops.count("queue full") == 1);
    CHECK(lr.sources[0].drops.at("queue full").count + static_cast<std::uint64_t>(s2.fused) == 40);
  }
}

namespace {

// A live source on the monotonic clock whose samples are handed over `lag_ms` after their
// stamps (a webcam: stamped at the exposure's start, delivered after readout and transfer).
class LaggingSource : public Source {
 public:
  LaggingSource(std::string name, TimeNs t0, int period_us, int lag_ms, int count)
      : name_(std::move(name)), t0_(t0), period_us_(period_us), lag_ms_(lag_ms), count_(count) {}
  std::string name() const override { return name_; }
  bool live() const override { return true; }
  bool next(SensorData& out) override {
    if (i_ >= count_) return false;
    FixSample f;
    f.t = t0_ + TimeNs{i_++} * period_us_ * 1000;
    std::this_thread::sleep_until(std::chrono::steady_clock::time_point(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::nanoseconds(f.t + TimeNs{lag_ms_} * 1'000'000))));
    out = f;
    return true;
  }

 private:
  std::string name_;
  TimeNs t0_;
  int period_us_, lag_ms_, count_;
  int i_ = 0;
};

}  // namespace

TEST_CASE("Live pipeline learns a source's lag and waits for it instead of dropping its samples", "[pipeline][live]") {
  // A 15 fps camera handed over 150 ms after its stamps beside a 200 Hz IMU with 2 ms: with
  // only the 60 ms reorder window every frame came after the merger had moved on. The first
  // frames (before the lag is known) may be late; after them, none.
  const TimeNs t0 = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch()).count() + 20'000'000;
  std::vector<SourcePtr> sources;
  sources.push_back(std::make_unique<LaggingSource>("imu", t0, 5000, 2, 400));       // 2 s
  sources.push_back(std::make_unique<LaggingSource>("camera", t0, 66667, 150, 30));  // 2 s
  PipelineOptions opt;
  opt.live = true;
  Pipeline p(std::move(sources), {}, opt);
  Recorder rec;
  const PipelineReport r = p.run(rec);
  const auto late = [&](int i) {
    const auto it = r.sources[static_cast<std::size_t>(i)].drops.find("late (older than the reorder window)");
    return it == r.sources[static_cast<std::size_t>(i)].drops.end() ? std::uint64_t{0} : it->second.count;
  };
  INFO("camera: " << r.sources[1].samples << " fused, " << late(1) << " late; imu " << r.sources[0].samples);
  CHECK(r.sources[0].samples == 400);
  CHECK(late(1) <= 3);
  CHECK(r.sources[1].samples + late(1) == 30);
  for (std::size_t i = 1; i < rec.seen.size(); ++i) REQUIRE(rec.seen[i - 1].first <= rec.seen[i].first);
  // The report carries the lag it learnt.
  CHECK(r.sources[1].lag_samples == 30);
  CHECK(r.sources[1].lag_mean_s == Approx(0.150).margin(0.03));
  CHECK(r.sources[0].lag_mean_s < 0.03);

  SECTION("a source later than max_source_lag is not waited for") {
    std::vector<SourcePtr> s2;
    const TimeNs t1 = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::steady_clock::now().time_since_epoch()).count() + 20'000'000;
    s2.push_back(std::make_unique<LaggingSource>("imu", t1, 5000, 2, 200));
    s2.push_back(std::make_unique<LaggingSource>("camera", t1, 66667, 150, 15));
    opt.max_source_lag = std::chrono::milliseconds(100);
    Pipeline p2(std::move(s2), {}, opt);
    Recorder rec2;
    const PipelineReport r2 = p2.run(rec2);
    CHECK(r2.sources[0].samples == 200);
    CHECK(r2.sources[1].samples <= 2);  // every frame but possibly the last ones is late
  }
}
