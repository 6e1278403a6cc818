// SerialImuSource through a socat pseudo-terminal pair with real byte streams.
#include <catch2/catch.hpp>
#include <chrono>
#include <numbers>
#include <cstdio>
#include <thread>
#include <vector>

#include "core/common/input_error.hpp"
#include "core/filter/fast_rng.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/serial/serial_imu_source.hpp"
#include "plugins/serial/serial_port.hpp"
#include "socat_pair.hpp"
#include "../source_reader.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace std::chrono_literals;

namespace {

constexpr double kAccLsb = 16.0 * 9.80665 / 32768.0;

// WitMotion cycle (acc, gyro, mag) whose acc x and gyro z carry the index k.
void append_cycle(std::vector<std::uint8_t>& b, int k) {
  const auto v = static_cast<std::int16_t>(k % 30000);
  for (const auto& p : {WitMotionParser::encode(0x51, {v, 0, 2048, 2500}), WitMotionParser::encode(0x52, {0, 0, v, 0}),
                        WitMotionParser::encode(0x54, {300, -200, -400, 0})})
    b.insert(b.end(), p.begin(), p.end());
}


SerialImuOptions witmotion_options(const std::string& path) {
  SerialImuOptions o;
  o.path = path;
  o.baud = 921600;
  o.protocol = SerialProtocol::witmotion;
  o.report_to_stderr = false;
  return o;
}

#define REQUIRE_SOCAT()                                                  \
  if (!test::SocatPair::available()) {                                   \
    WARN("socat not installed: serial pseudo-terminal test skipped");    \
    return;                                                              \
  }

}  // namespace

TEST_CASE("Serial IMU: 2000 samples/s of WitMotion with garbage and split writes through a pty, none lost", "[imu]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("serial_fast"));
  REQUIRE(pty.running());
  SerialImuSource source(witmotion_options(pty.b()));
  SerialPort writer(pty.a(), 921600);
  constexpr int kSamples = 4000;  // 2 s at 2000 Hz
  test::SourceReader<ImuSample> reader(source, kSamples);
  FastRng rng(21);
  std::size_t garbage = 0;
  const auto t0 = std::chrono::steady_clock::now();
  auto t_written = t0;  // end of the last write
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < kSamples; ++k) {
    if (k % 3 == 0) {  // garbage before every third sample, 0x55 headers included
      const int n = 1 + static_cast<int>(rng.uniform() * 12);
      for (int i = 0; i < n; ++i) bytes.push_back(rng.uniform() < 0.2 ? 0x55 : static_cast<std::uint8_t>(rng.uniform() * 256));
      garbage += static_cast<std::size_t>(n);
    }
    append_cycle(bytes, k);
    if (k % 10 == 9) {  // every 5 ms, in writes of random sizes that split packets anywhere
      std::size_t i = 0;
      while (i < bytes.size()) {
        const std::size_t n = std::min(bytes.size() - i, 1 + static_cast<std::size_t>(rng.uniform() * 60));
        writer.write_all(bytes.data() + i, n);
        i += n;
      }
      t_written = std::chrono::steady_clock::now();
      bytes.clear();
      std::this_thread::sleep_until(t0 + std::chrono::microseconds(500) * (k + 1));
    }
  }
  REQUIRE(reader.join_within(3s));
  REQUIRE(reader.samples.size() == kSamples);
  for (int k = 0; k < kSamples; ++k) REQUIRE(std::lround(reader.samples[k].acc_inB.x() / kAccLsb) == k);
  for (int k = 1; k < kSamples; ++k) REQUIRE(reader.samples[k].t > reader.samples[k - 1].t);
  // Kept up: the last sample was out 50 ms after the last write at most.
  const double lag_ms = std::chrono::duration<double, std::milli>(reader.arrival.back() - t_written).count();
  const double span_s = ns_to_seconds(reader.samples.back().t - reader.samples.front().t);
  std::printf("[imu] serial pty: %d samples in %.3f s of arrival time, lag after the last write %.1f ms, %llu "
              "garbage bytes skipped\n",
              kSamples, span_s, lag_ms, static_cast<unsigned long long>(source.drops().count(serial_drop::kSkippedBytes)));
  CHECK(lag_ms < 50.0);
  CHECK(span_s == Approx(2.0).margin(0.2));
  CHECK(source.drops().count(serial_drop::kSkippedBytes) == garbage);
  CHECK(source.drops().count(serial_drop::kIncompleteSample) == 0);
  CHECK(source.failure().empty());
}

TEST_CASE("Serial IMU: CSV lines through a pty, via the serial-imu source kind", "[imu]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("serial_csv"));
  REQUIRE(pty.running());
  SourcePtr source = make_live_source(
      SourceSpec::parse("serial-imu:" + pty.b() + ",baud=115200,protocol=csv,columns=ax:ay:az:gx:gy:gz,gyro_unit=dps,axes=+y-x+z"));
  REQUIRE(source->live());
  SerialPort writer(pty.a(), 115200);
  test::SourceReader<ImuSample> reader(*source, 3);
  const std::string text = "0.1,0.2,9.8,90,0,0\nnot a sample\n0.1,0.2,9.8,0,90,0\n0.1,0.2,9.8,0,0,90\n";
  writer.write_all(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  REQUIRE(reader.join_within(2s));
  REQUIRE(reader.samples.size() == 3);
  // Axes +y-x+z: body x = sensor y, body y = -sensor x.
  CHECK(reader.samples[0].acc_inB.x() == Approx(0.2));
  CHECK(reader.samples[0].acc_inB.y() == Approx(-0.1));
  CHECK(reader.samples[0].gyro_inB.y() == Approx(-std::numbers::pi / 2));
  CHECK(reader.samples[1].gyro_inB.x() == Approx(std::numbers::pi / 2));
  CHECK(source->drops().count(serial_drop::kBadLine) == 1);
}

TEST_CASE("Serial IMU: the writer vanishing ends the stream with a failure (on_loss=end)", "[imu]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("serial_loss_end"));
  REQUIRE(pty.running());
  SerialImuSource source(witmotion_options(pty.b()));
  test::SourceReader<ImuSample> reader(source, 1000000);
  {
    SerialPort writer(pty.a(), 921600);
    std::vector<std::uint8_t> bytes;
    for (int k = 0; k < 100; ++k) append_cycle(bytes, k);
    writer.write_all(bytes.data(), bytes.size());
    std::this_thread::sleep_for(100ms);
  }
  pty.stop();  // the device vanishes (socat gone: the pty hangs up, like a USB adapter pulled)
  REQUIRE(reader.join_within(3s));
  CHECK(reader.samples.size() == 100);
  CHECK_THAT(source.failure(), Catch::Contains("device lost"));
  CHECK(source.losses() == 1);
}

TEST_CASE("Serial IMU: on_loss=wait survives the device going away and coming back", "[imu]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("serial_loss_wait"));
  REQUIRE(pty.running());
  SerialImuOptions o = witmotion_options(pty.b());
  o.on_loss = OnLoss::wait;
  o.reopen_interval_s = 0.05;
  SerialImuSource source(o);
  test::SourceReader<ImuSample> reader(source, 200);
  auto send = [&](int from) {
    SerialPort writer(pty.a(), 921600);
    std::vector<std::uint8_t> bytes;
    for (int k = from; k < from + 100; ++k) append_cycle(bytes, k);
    writer.write_all(bytes.data(), bytes.size());
    std::this_thread::sleep_for(100ms);
  };
  send(0);
  pty.stop();  // unplugged
  std::this_thread::sleep_for(300ms);
  CHECK_FALSE(reader.done);  // still waiting for the device
  REQUIRE(pty.start());     // plugged back in (same path)
  std::this_thread::sleep_for(200ms);
  send(100);
  REQUIRE(reader.join_within(3s));
  REQUIRE(reader.samples.size() == 200);
  CHECK(std::lround(reader.samples[150].acc_inB.x() / kAccLsb) == 150);
  CHECK(source.drops().count(serial_drop::kDeviceLost) == 1);
  CHECK(source.failure().empty());
}

TEST_CASE("Serial IMU: request_stop unblocks a waiting next(), bad specs are input errors", "[imu]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("serial_stop"));
  REQUIRE(pty.running());
  SerialImuSource source(witmotion_options(pty.b()));
  test::SourceReader<ImuSample> reader(source, 10);
  std::this_thread::sleep_for(100ms);
  const auto t = std::chrono::steady_clock::now();
  source.request_stop();
  REQUIRE(reader.join_within(1s));
  CHECK(std::chrono::steady_clock::now() - t < 100ms);
  CHECK(reader.samples.empty());
  CHECK(source.failure().empty());

  auto spec_error = [&](const std::string& extra) {
    try {
      make_live_source(SourceSpec::parse("serial-imu:" + pty.b() + extra));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(spec_error(",baud=12345"), Catch::Contains("'baud'") && Catch::Contains("standard"));
  CHECK_THAT(spec_error(",protocol=nmea"), Catch::Contains("'protocol'"));
  CHECK_THAT(spec_error(",on_loss=retry"), Catch::Contains("'on_loss'"));
  CHECK_THAT(spec_error(",axes=+x+x+z"), Catch::Contains("'axes'"));
  CHECK_THAT(spec_error(",colour=red"), Catch::Contains("'colour'") && Catch::Contains("unknown option"));
  CHECK_THROWS_WITH(make_live_source(SourceSpec::parse("serial-imu:/nonexistent/tty")),
                    Catch::Contains("cannot open serial port"));
}
