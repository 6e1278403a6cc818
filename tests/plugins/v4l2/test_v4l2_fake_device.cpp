// The real V4l2Camera / V4l2CameraSource code driven through an ioctl-level fake device
// (fake_v4l2_device.*): format negotiation, mmap buffer cycling, driver time stamps,
// exposure controls, and the faults of a live camera (EBUSY, ENODEV mid-stream, poll
// timeouts, a truncated frame). No camera is needed, and none was tried.
#include <catch2/catch.hpp>
#include <chrono>
#include <ctime>
#include <opencv2/core.hpp>
#include <thread>

#include "core/pipeline/pipeline.hpp"
#include "plugins/serial/monotonic_clock.hpp"
#include "plugins/source_spec.hpp"
#include "plugins/v4l2/buffer_time.hpp"
#include "plugins/v4l2/fake_v4l2_device.hpp"
#include "plugins/v4l2/v4l2_camera_source.hpp"
#include "../source_reader.hpp"

using namespace luxloc;
using namespace std::chrono_literals;

namespace {

std::vector<std::uint8_t> yuyv_frame(int w, int h, std::uint8_t y) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(2 * w * h));
  for (std::size_t i = 0; i < b.size(); i += 2) {
    b[i] = y;
    b[i + 1] = 128;
  }
  return b;
}

std::vector<std::uint8_t> grey_frame(int w, int h, std::uint8_t v) {
  return std::vector<std::uint8_t>(static_cast<std::size_t>(w * h), v);
}

TimeNs realtime_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * kNsPerSecond + ts.tv_nsec;
}

V4l2CameraOptions small(int w = 64, int h = 48) {
  V4l2CameraOptions o;
  o.path = "/dev/video-fake";
  o.width = w;
  o.height = h;
  o.exposure_us.reset();  // auto: no controls needed unless a test asks
  return o;
}

// UVC-style exposure controls with the current kernel names (or the old ones).
void add_exposure_controls(test::FakeV4l2Device& dev, bool old_names) {
  test::FakeControl ae;
  ae.id = V4L2_CID_EXPOSURE_AUTO;
  ae.name = old_names ? "Exposure, Auto" : "Auto Exposure";
  ae.type = V4L2_CTRL_TYPE_MENU;
  ae.minimum = 0;
  ae.maximum = 3;
  ae.value = ae.default_value = 3;
  ae.menu = {{1, "Manual Mode"}, {3, "Aperture Priority Mode"}};
  test::FakeControl prio;
  prio.id = V4L2_CID_EXPOSURE_AUTO_PRIORITY;
  prio.name = old_names ? "Exposure, Auto Priority" : "Exposure, Dynamic Framerate";
  prio.type = V4L2_CTRL_TYPE_BOOLEAN;
  prio.maximum = 1;
  prio.value = 1;
  test::FakeControl abs;
  // An old driver: the exposure under a private id, found by its old name only.
  abs.id = old_names ? V4L2_CID_CAMERA_CLASS_BASE + 0x90 : V4L2_CID_EXPOSURE_ABSOLUTE;
  abs.name = old_names ? "Exposure (Absolute)" : "Exposure Time, Absolute";
  abs.minimum = 3;
  abs.maximum = 2047;
  abs.value = abs.default_value = 250;
  dev.controls = {ae, prio, abs};
}

}  // namespace

TEST_CASE("V4L2 fake device: the driver picks another size and format, taken with notes", "[v4l2]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  dev->formats = {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_YUYV};
  dev->actual_fps = 25.0;
  dev->adjust_format = [](v4l2_pix_format& p) {  // a camera with one YUYV mode only
    p.pixelformat = V4L2_PIX_FMT_YUYV;
    p.width = 32;
    p.height = 24;
  };
  {
    V4l2Camera cam(small(), dev);  // asks for GREY (the best native), 64x48, 30 fps
    CHECK(cam.format() == PixelFormat::yuyv);
    CHECK(cam.width() == 32);
    CHECK(cam.height() == 24);
    CHECK(cam.fps() == Approx(25.0));
    std::string notes;
    for (const auto& n : cam.notes()) notes += n + "\n";
    CHECK_THAT(notes, Catch::Contains("asked for 64x48, the camera set 32x24") &&
                          Catch::Contains("asked for GREY, the driver set YUYV") &&
                          Catch::Contains("the camera set 25.00 fps"));
    // Frames of the mode the driver chose convert.
    REQUIRE(dev->push_frame({yuyv_frame(32, 24, 77)}));
    cv::Mat gray;
    TimeNs t = 0;
    REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
    CHECK(gray.cols == 32);
    CHECK(gray.rows == 24);
    CHECK(gray.at<std::uint8_t>(10, 10) == 77);
  }
  // A format the user named is not swapped silently; one we cannot convert is refused.
  V4l2CameraOptions grey = small();
  grey.format = PixelFormat::grey;
  CHECK_THROWS_WITH(V4l2Camera(grey, dev), Catch::Contains("asked for GREY, the driver set YUYV"));
  dev->adjust_format = [](v4l2_pix_format& p) { p.pixelformat = V4L2_PIX_FMT_RGB24; };
  try {
    V4l2Camera cam(small(), dev);
    FAIL("no error");
  } catch (const V4l2Error& e) {
    CHECK(e.kind() == V4l2Error::Kind::unsupported_format);
    CHECK_THAT(e.what(), Catch::Contains("RGB3") && Catch::Contains("cannot be converted"));
  }
  CHECK(dev->counts().opens == dev->counts().closes);  // every failed open closed its descriptor
  CHECK(dev->counts().mapped == 0);
}

TEST_CASE("V4L2 fake device: mmap buffers cycle in queue order, every frame's pixels arrive intact", "[v4l2]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  dev->formats = {V4L2_PIX_FMT_GREY};
  V4l2CameraOptions o = small();
  o.buffers = 4;
  {
    V4l2Camera cam(o, dev);
    CHECK(dev->counts().mapped == 4);
    CHECK(dev->counts().streamons == 1);
    cv::Mat gray;
    TimeNs t = 0;
    for (int k = 0; k < 12; ++k) {
      REQUIRE(dev->push_frame({grey_frame(64, 48, static_cast<std::uint8_t>(10 + k))}));
      REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
      CHECK(gray.at<std::uint8_t>(0, 0) == 10 + k);
      CHECK(gray.at<std::uint8_t>(47, 63) == 10 + k);
    }
    // The driver holds at most the 4 queued buffers: a 5th frame before any DQBUF is an overrun.
    for (int k = 0; k < 5; ++k) dev->push_frame({grey_frame(64, 48, static_cast<std::uint8_t>(100 + k))});
    CHECK(dev->counts().overruns == 1);
    for (int k = 0; k < 4; ++k) {
      REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
      CHECK(gray.at<std::uint8_t>(5, 5) == 100 + k);  // oldest first
    }
    const std::vector<std::uint32_t> order = dev->dequeued();
    REQUIRE(order.size() == 16);
    for (std::size_t k = 0; k < order.size(); ++k) CHECK(order[k] == k % 4);
    // The converted frame owns its pixels: refilling the buffer does not change it.
    const cv::Mat kept = gray.clone();
    REQUIRE(dev->push_frame({grey_frame(64, 48, 1)}));
    CHECK(cv::countNonZero(gray != kept) == 0);
  }
  // Destruction: stream off, every buffer unmapped, the descriptor closed.
  const auto c = dev->counts();
  CHECK(c.streamoffs == 1);
  CHECK(c.mapped == 0);
  CHECK(c.closes == c.opens);
}

TEST_CASE("V4L2 buffer time stamps: monotonic, realtime (old drivers) and arrival, onto our timeline", "[v4l2]") {
  const TimeNs mono = 5'000 * kNsPerSecond, real = 1'700'000'000 * kNsPerSecond;
  const TimeNs d = 30'000'000;  // exposed 30 ms before the dequeue
  BufferTime b = buffer_time(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, mono - d, mono, real);
  CHECK(b.clock == BufferClock::monotonic);
  CHECK(b.t == mono - d);
  b = buffer_time(V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN, real - d, mono, real);
  CHECK(b.clock == BufferClock::realtime);
  CHECK(b.t == mono - d);
  b = buffer_time(V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN, mono - d, mono, real);  // unflagged, but monotonic
  CHECK(b.clock == BufferClock::monotonic);
  CHECK(b.t == mono - d);
  for (std::uint32_t flags : {V4L2_BUF_FLAG_TIMESTAMP_COPY, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC}) {
    b = buffer_time(flags, mono - 3600 * kNsPerSecond, mono, real);  // an hour old: not believed
    CHECK(b.clock == BufferClock::arrival);
    CHECK(b.t == mono);
  }
  b = buffer_time(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, 0, mono, real);  // no stamp
  CHECK(b.clock == BufferClock::arrival);

  // Through the camera: the stamps the fake driver writes come out on the monotonic clock.
  auto dev = std::make_shared<test::FakeV4l2Device>();
  V4l2Camera cam(small(), dev);
  cv::Mat gray;
  TimeNs t = 0;
  const TimeNs m_stamp = monotonic_now_ns() - d;
  REQUIRE(dev->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, m_stamp}));
  REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK(t == m_stamp / 1000 * 1000);  // microsecond resolution of struct timeval
  CHECK(cam.clock() == BufferClock::monotonic);
  const TimeNs m_before = monotonic_now_ns();
  REQUIRE(dev->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN, realtime_now_ns() - d}));
  REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK(cam.clock() == BufferClock::realtime);
  CHECK(std::abs((t - (m_before - d)) / 1'000'000) <= 5);  // within 5 ms of the exposure
  CHECK_FALSE(cam.arrival_stamped());
  REQUIRE(dev->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_COPY, 123}));
  const TimeNs a_before = monotonic_now_ns();
  REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK(cam.arrival_stamped());
  CHECK(t >= a_before);
  CHECK(t <= monotonic_now_ns());
}

TEST_CASE("V4L2 end-of-frame stamps are moved back to row 0's exposure start when the row time is known", "[v4l2]") {
  const TimeNs mono = 5'000 * kNsPerSecond, real = 1'700'000'000 * kNsPerSecond, d = 30'000'000;
  // TSTAMP_SRC_EOF is the API's default (0); uvcvideo declares SOE.
  CHECK(buffer_time(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF, mono - d, mono, real).end_of_frame);
  CHECK_FALSE(buffer_time(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE, mono - d, mono, real).end_of_frame);
  CHECK(buffer_time(V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN, real - d, mono, real).end_of_frame);
  CHECK_FALSE(buffer_time(V4L2_BUF_FLAG_TIMESTAMP_COPY, 123, mono, real).end_of_frame);  // arrival: no driver stamp

  auto dev = std::make_shared<test::FakeV4l2Device>();
  V4l2CameraOptions o = small();
  o.row_time_us = 30.0;
  V4l2Camera cam(o, dev);  // the fake sets 32x24
  cv::Mat gray;
  TimeNs t = 0;
  const TimeNs stamp = monotonic_now_ns() - d;
  const double exposure_us = cam.exposure_us().value_or(0.0);
  const TimeNs shift = std::llround((exposure_us + (cam.height() - 1) * 30.0) * 1000.0);
  CHECK(cam.end_of_frame_shift_ns() == shift);
  CHECK(shift >= 23 * 30'000);
  REQUIRE(dev->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF, stamp}));
  REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK(cam.end_of_frame_stamped());
  CHECK(t == stamp / 1000 * 1000 - shift);
  REQUIRE(dev->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE, stamp + d}));
  REQUIRE(cam.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK_FALSE(cam.end_of_frame_stamped());
  CHECK(t == (stamp + d) / 1000 * 1000);  // the start of exposure: as is

  // Without the row time the stamp stays (and the source says the frames are late).
  auto dev2 = std::make_shared<test::FakeV4l2Device>();
  V4l2Camera plain(small(), dev2);
  CHECK(plain.end_of_frame_shift_ns() == 0);
  REQUIRE(dev2->push_frame({yuyv_frame(64, 48, 1), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, stamp}));
  REQUIRE(plain.grab(1000, -1, gray, t) == V4l2Camera::GrabStatus::frame);
  CHECK(plain.end_of_frame_stamped());
  CHECK(t == stamp / 1000 * 1000);
}

TEST_CASE("V4L2 fake device: exposure controls that the driver clamps, ignores or names the old way", "[v4l2]") {
  SECTION("current names: auto off first, dynamic frame rate off, then the exposure; a clamp is reported") {
    auto dev = std::make_shared<test::FakeV4l2Device>();
    add_exposure_controls(*dev, false);
    dev->controls[2].behaviour = test::FakeControl::Behaviour::clamp;
    dev->controls[2].clamp_max = 333;  // the frame interval at 30 fps caps it below the reported 2047
    V4l2CameraOptions o = small();
    o.exposure_us = 50'000.0;  // 500 units: within the reported range
    V4l2Camera cam(o, dev);
    const auto set = dev->controls_set();
    REQUIRE(set.size() == 3);
    CHECK(set[0] == std::make_pair<std::uint32_t, std::int32_t>(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL));
    CHECK(set[1] == std::make_pair<std::uint32_t, std::int32_t>(V4L2_CID_EXPOSURE_AUTO_PRIORITY, 0));
    CHECK(set[2] == std::make_pair<std::uint32_t, std::int32_t>(V4L2_CID_EXPOSURE_ABSOLUTE, 500));
    REQUIRE(cam.exposure_us());
    CHECK(*cam.exposure_us() == Approx(33'300.0));  // what the camera reads back
    std::string notes;
    for (const auto& n : cam.notes()) notes += n + "\n";
    CHECK_THAT(notes, Catch::Contains("reads back 333") && Catch::Contains("clamped"));
  }
  SECTION("below the range: clamped to the minimum before setting, said in a note") {
    auto dev = std::make_shared<test::FakeV4l2Device>();
    add_exposure_controls(*dev, false);
    V4l2CameraOptions o = small();
    o.exposure_us = 100.0;  // 1 unit; this camera's minimum is 3 (C920-class, FIELD_NOTES)
    V4l2Camera cam(o, dev);
    CHECK(*cam.exposure_us() == Approx(300.0));
    CHECK(dev->control(V4L2_CID_EXPOSURE_ABSOLUTE)->value == 3);
    std::string notes;
    for (const auto& n : cam.notes()) notes += n + "\n";
    CHECK_THAT(notes, Catch::Contains("300"));
  }
  SECTION("a driver that ignores the exposure: reported, the real exposure is what it reads back") {
    auto dev = std::make_shared<test::FakeV4l2Device>();
    add_exposure_controls(*dev, false);
    dev->controls[2].behaviour = test::FakeControl::Behaviour::ignore;
    V4l2CameraOptions o = small();
    o.exposure_us = 1000.0;
    V4l2Camera cam(o, dev);
    CHECK(*cam.exposure_us() == Approx(25'000.0));
    std::string notes;
    for (const auto& n : cam.notes()) notes += n + "\n";
    CHECK_THAT(notes, Catch::Contains("ignored the setting"));
  }
  SECTION("old kernel names, the exposure under another id: found by name and set") {
    auto dev = std::make_shared<test::FakeV4l2Device>();
    add_exposure_controls(*dev, true);
    V4l2CameraOptions o = small();
    o.exposure_us = 500.0;
    V4l2Camera cam(o, dev);
    CHECK(dev->control(V4L2_CID_CAMERA_CLASS_BASE + 0x90)->value == 5);
    CHECK(dev->control(V4L2_CID_EXPOSURE_AUTO)->value == V4L2_EXPOSURE_MANUAL);
    CHECK(dev->control(V4L2_CID_EXPOSURE_AUTO_PRIORITY)->value == 0);
    CHECK(*cam.exposure_us() == Approx(500.0));
  }
  SECTION("no exposure control at all: a clear error listing the controls") {
    auto dev = std::make_shared<test::FakeV4l2Device>();
    test::FakeControl gain;
    gain.id = V4L2_CID_GAIN;
    gain.name = "Gain";
    gain.maximum = 255;
    dev->controls = {gain};
    V4l2CameraOptions o = small();
    o.exposure_us = 100.0;
    try {
      V4l2Camera cam(o, dev);
      FAIL("no error");
    } catch (const V4l2Error& e) {
      CHECK(e.kind() == V4l2Error::Kind::no_manual_exposure);
      CHECK_THAT(e.what(), Catch::Contains("gain (0..255)") && Catch::Contains("exposure_us=auto"));
    }
    CHECK(dev->counts().closes == dev->counts().opens);
  }
}

TEST_CASE("Live fault: V4L2 device busy (EBUSY at open and at VIDIOC_S_FMT)", "[v4l2][live-fault]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  dev->open_errno = EBUSY;
  try {
    V4l2CameraSource src(small(), {}, dev);
    FAIL("no error");
  } catch (const V4l2Error& e) {
    CHECK(e.kind() == V4l2Error::Kind::busy);
    CHECK_THAT(e.what(), Catch::Contains("/dev/video-fake") && Catch::Contains("busy"));
  }
  dev->open_errno = 0;
  dev->s_fmt_errno = EBUSY;  // opens, but another program streams
  try {
    V4l2CameraSource src(small(), {}, dev);
    FAIL("no error");
  } catch (const V4l2Error& e) {
    CHECK(e.kind() == V4l2Error::Kind::busy);
    CHECK_THAT(e.what(), Catch::Contains("another program is streaming"));
  }
  CHECK(dev->counts().closes == dev->counts().opens);
}

TEST_CASE("Live fault: V4L2 unplugged mid-stream (ENODEV), on_loss=end: clear failure, every pose flushed", "[v4l2][live-fault]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  std::vector<SourcePtr> sources;
  V4l2LossOptions loss;
  loss.report_to_stderr = false;
  sources.push_back(std::make_unique<V4l2CameraSource>(small(), loss, dev));
  // One pose per frame, into a sink that counts what it was given and flushed.
  struct PerFrame final : FusionStage {
    void process(const Sample& s, std::vector<PoseEstimate>& out) override {
      PoseEstimate p;
      p.t = s.t;
      out.push_back(p);
    }
  } stage;
  struct Counter final : PoseSink {
    std::atomic<int>* written;
    std::atomic<bool>* flushed;
    std::string name() const override { return "counter"; }
    void write(const PoseEstimate&) override { ++*written; }
    void flush() override { *flushed = true; }
  };
  std::atomic<int> written{0};
  std::atomic<bool> flushed{false};
  auto sink = std::make_unique<Counter>();
  sink->written = &written;
  sink->flushed = &flushed;
  std::vector<PoseSinkPtr> sinks;
  sinks.push_back(std::move(sink));
  PipelineOptions po;
  po.live = true;
  Pipeline pipeline(std::move(sources), std::move(sinks), po);
  std::thread sensor([&] {
    for (int k = 0; k < 20; ++k) {
      while (!dev->push_frame({yuyv_frame(64, 48, 50), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC,
                               monotonic_now_ns()}))
        std::this_thread::sleep_for(1ms);
      std::this_thread::sleep_for(5ms);
    }
    dev->unplug();
  });
  const PipelineReport r = pipeline.run(stage);
  sensor.join();
  REQUIRE(r.sources.size() == 1);
  CHECK(r.sources[0].samples == 20);
  CHECK_THAT(r.sources[0].failure, Catch::Contains("v4l2:/dev/video-fake") && Catch::Contains("device lost"));
  CHECK(written == 20);  // every pose computed before the loss reached the sink
  CHECK(flushed);
  CHECK(dev->counts().mapped == 0);
  CHECK(dev->counts().closes == dev->counts().opens);
}

TEST_CASE("Live fault: V4L2 unplugged and plugged back, on_loss=wait: re-opened, frames resume", "[v4l2][live-fault]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  V4l2LossOptions loss = V4l2LossOptions::from_spec(SourceSpec::parse("v4l2:/dev/video-fake,on_loss=wait"));
  CHECK(loss.on_loss == OnLoss::wait);
  loss.reopen_interval_s = 0.05;
  loss.report_to_stderr = false;
  V4l2CameraSource src(small(), loss, dev);
  test::SourceReader<FrameSample> reader(src, 10);
  const auto send = [&](int n, std::uint8_t v) {
    for (int k = 0; k < n; ++k) {
      const auto end = std::chrono::steady_clock::now() + 2s;
      while (!dev->push_frame({yuyv_frame(64, 48, v), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC,
                               monotonic_now_ns()}) &&
             std::chrono::steady_clock::now() < end)
        std::this_thread::sleep_for(1ms);
      std::this_thread::sleep_for(5ms);
    }
  };
  send(5, 60);
  std::this_thread::sleep_for(50ms);
  dev->unplug();
  std::this_thread::sleep_for(300ms);  // several failed re-opens
  CHECK_FALSE(reader.done);
  dev->replug();
  send(5, 90);
  REQUIRE(reader.join_within(3s));
  REQUIRE(reader.samples.size() == 10);
  CHECK(reader.samples[4].gray.at<std::uint8_t>(0, 0) == 60);
  CHECK(reader.samples[9].gray.at<std::uint8_t>(0, 0) == 90);
  CHECK(reader.samples[9].t > reader.samples[4].t);
  CHECK(src.losses() == 1);
  CHECK(src.drops().count("device lost") == 1);
  CHECK_THAT(src.drops().snapshot().at("device lost").first_message, Catch::Contains("device lost"));
  CHECK(src.failure().empty());
  CHECK(dev->counts().opens == 2);
}

TEST_CASE("Live fault: V4L2 poll timeouts: the source waits, counts them, and stops on request", "[v4l2][live-fault]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  V4l2LossOptions loss;
  loss.poll_timeout_ms = 20;
  loss.silent_warn_s = 0.1;
  loss.report_to_stderr = false;
  V4l2CameraSource src(small(), loss, dev);
  test::SourceReader<FrameSample> reader(src, 1);
  std::this_thread::sleep_for(300ms);
  CHECK_FALSE(reader.done);
  CHECK(src.timeouts() >= 5);
  const auto t0 = std::chrono::steady_clock::now();
  src.request_stop();
  REQUIRE(reader.join_within(1s));
  CHECK(std::chrono::steady_clock::now() - t0 < 500ms);  // woken through the pipe, not by a timeout
  CHECK(reader.samples.empty());
  CHECK(src.failure().empty());
}

TEST_CASE("Live fault: V4L2 truncated frame (bytesused short) and a driver-flagged corrupt buffer are skipped and counted", "[v4l2][live-fault]") {
  auto dev = std::make_shared<test::FakeV4l2Device>();
  V4l2LossOptions loss;
  loss.report_to_stderr = false;
  V4l2CameraSource src(small(), loss, dev);
  test::SourceReader<FrameSample> reader(src, 2);
  const TimeNs t0 = monotonic_now_ns();
  auto frame = [&](std::uint8_t v, int k) {
    return test::FakeFrame{yuyv_frame(64, 48, v), std::nullopt, V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, t0 + k * 1'000'000};
  };
  REQUIRE(dev->push_frame(frame(10, 1)));
  test::FakeFrame cut = frame(20, 2);
  cut.bytesused = 64 * 48;  // half of a YUYV frame arrived
  REQUIRE(dev->push_frame(cut));
  test::FakeFrame corrupt = frame(30, 3);
  corrupt.error = true;
  REQUIRE(dev->push_frame(corrupt));
  REQUIRE(dev->push_frame(frame(40, 4)));
  REQUIRE(reader.join_within(2s));
  REQUIRE(reader.samples.size() == 2);
  CHECK(reader.samples[0].gray.at<std::uint8_t>(0, 0) == 10);
  CHECK(reader.samples[1].gray.at<std::uint8_t>(0, 0) == 40);
  CHECK(src.drops().count("bad frame") == 2);
  CHECK_THAT(src.drops().snapshot().at("bad frame").first_message,
             Catch::Contains("buffer holds 3072 bytes") && Catch::Contains("6144"));
}
