// The session recorder: what it writes reads back exactly through the playback sources;
// a full queue drops and counts instead of blocking; an existing session is not overwritten.
#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/core.hpp>

#include "core/common/input_error.hpp"
#include "plugins/playback/playback_session.hpp"
#include "plugins/record/session_recorder.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

Sample sample_of(SensorData d) {
  Sample s;
  s.t = sample_time(d);
  s.data = std::move(d);
  return s;
}

}  // namespace

TEST_CASE("Recorder: times and values round-trip exactly through playback", "[io]") {
  const auto dir = test::scratch_dir("recorder_roundtrip") / "s";
  std::vector<PoseEstimate> none;
  ImuSample a;
  a.t = 12345'678901234;  // 12345.678901234 s
  a.acc_inB = {0.1, -1.0 / 3.0, 9.80665};
  a.gyro_inB = {1e-9, -2.5e-3, M_PI};
  a.mag_inB = {21.5, -4.25, -42.0 / 7.0};
  a.has_mag = true;
  ImuSample b = a;
  b.t += 10'000'001;
  b.has_mag = false;
  FrameSample f;
  f.t = a.t + 5'000'000;
  f.gray = cv::Mat(48, 64, CV_8UC1);
  cv::randu(f.gray, 0, 256);
  FixSample x;
  x.t = b.t + 1;
  x.p_inW = {1.0 / 7.0, 2e-7};
  {
    SessionRecorder rec(dir, std::nullopt, std::nullopt, SessionConfig{});
    for (SensorData d : {SensorData(a), SensorData(f), SensorData(b), SensorData(x)}) rec.process(sample_of(d), none);
    rec.finish(none);
    const RecorderStats st = rec.stats();
    CHECK(st.written.at("imu.csv") == 2);
    CHECK(st.written.at("frames.csv") == 1);
    CHECK(st.written.at("fixes.csv") == 1);
    CHECK(st.dropped.empty());
  }
  PlaybackSession s = open_playback(dir.string(), {});
  std::vector<SensorData> got;
  for (auto& src : s.sources) {
    SensorData d;
    while (src->next(d)) got.push_back(d);
    CHECK(src->drops().total() == 0);
  }
  REQUIRE(got.size() == 4);
  int imu = 0;
  for (const SensorData& d : got) {
    if (const auto* i = std::get_if<ImuSample>(&d)) {
      const ImuSample& want = imu++ == 0 ? a : b;
      CHECK(i->t == want.t);
      CHECK(i->acc_inB == want.acc_inB);  // bit-exact
      CHECK(i->gyro_inB == want.gyro_inB);
      CHECK(i->has_mag == want.has_mag);
      if (want.has_mag) CHECK(i->mag_inB == want.mag_inB);
    } else if (const auto* fr = std::get_if<FrameSample>(&d)) {
      CHECK(fr->t == f.t);
      CHECK(cv::norm(fr->gray, f.gray, cv::NORM_INF) == 0.0);  // lossless
    } else if (const auto* fx = std::get_if<FixSample>(&d)) {
      CHECK(fx->t == x.t);
      CHECK(fx->p_inW == x.p_inW);
      CHECK(std::isnan(fx->sigma_m));
    }
  }
  CHECK(imu == 2);
  // A folder that already holds a session is refused.
  CHECK_THROWS_AS(SessionRecorder(dir, std::nullopt, std::nullopt, SessionConfig{}), InputError);
}

TEST_CASE("Recorder: a full queue drops and counts, never blocks the producer", "[io]") {
  const auto dir = test::scratch_dir("recorder_drops") / "s";
  RecorderOptions o;
  o.queue_capacity = 16;
  SessionRecorder rec(dir, std::nullopt, std::nullopt, SessionConfig{}, o);
  std::vector<PoseEstimate> none;
  FrameSample f;
  f.gray = cv::Mat(480, 640, CV_8UC1);
  cv::randu(f.gray, 0, 256);  // incompressible: ~10 ms a PNG
  const int n = 400;
  for (int k = 0; k < n; ++k) {
    f.t = k * 33'000'000LL;
    rec.process(sample_of(f), none);
  }
  rec.finish(none);
  const RecorderStats st = rec.stats();
  const std::uint64_t written = st.written.count("frames.csv") ? st.written.at("frames.csv") : 0;
  const std::uint64_t dropped = st.dropped.count("frames.csv") ? st.dropped.at("frames.csv") : 0;
  CHECK(written + dropped == n);
  CHECK(dropped > 0);
  CHECK(written >= 16);
}
