#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/filter/fast_rng.hpp"
#include "plugins/serial/witmotion_parser.hpp"

using namespace luxloc;

namespace {

// One output cycle (acc, gyro, angles, mag) for sample k: acc x carries k so order and
// completeness can be checked.
std::vector<std::uint8_t> cycle(int k) {
  std::vector<std::uint8_t> b;
  auto add = [&](std::uint8_t type, std::array<std::int16_t, 4> w) {
    const auto p = WitMotionParser::encode(type, w);
    b.insert(b.end(), p.begin(), p.end());
  };
  add(0x51, {static_cast<std::int16_t>(k), 0, 2048, 2534});    // az = 1 g, 25.34 C
  add(0x52, {16384, -16384, static_cast<std::int16_t>(k), 0});  // +-1000 deg/s
  add(0x53, {8192, 0, -16384, 0});                              // 45, 0, -90 deg
  add(0x54, {300, -200, static_cast<std::int16_t>(-400 - k), 0});
  return b;
}

std::vector<ImuSample> parse(const std::vector<std::uint8_t>& bytes, DropCounts& drops, std::size_t chunk) {
  WitMotionParser p(drops);
  std::vector<ImuSample> out;
  for (std::size_t i = 0; i < bytes.size(); i += chunk)
    p.feed(bytes.data() + i, std::min(chunk, bytes.size() - i), static_cast<TimeNs>(i), 0.0, out);
  return out;
}

}  // namespace

TEST_CASE("WitMotion: decodes a clean stream with the documented scaling", "[imu]") {
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < 50; ++k) {
    auto c = cycle(k);
    bytes.insert(bytes.end(), c.begin(), c.end());
  }
  DropCounts drops;
  WitMotionParser p(drops);
  std::vector<ImuSample> out;
  p.feed(bytes.data(), bytes.size(), 0, 0.0, out);
  REQUIRE(out.size() == 50);
  CHECK(drops.total() == 0);
  CHECK(p.packets() == 200);
  const double g = 9.80665, k_acc = 16.0 * g / 32768.0;
  CHECK(out[7].acc_inB.x() == Approx(7 * k_acc));
  CHECK(out[7].acc_inB.z() == Approx(g));
  CHECK(out[7].gyro_inB.x() == Approx(1000.0 * std::numbers::pi / 180.0));
  CHECK(out[7].gyro_inB.y() == Approx(-1000.0 * std::numbers::pi / 180.0));
  REQUIRE(out[7].has_mag);
  CHECK(out[7].mag_inB.z() == Approx(-407.0));  // counts (mag_scale 1)
  CHECK(p.temperature_c() == Approx(25.34));
  CHECK(p.device_angles_deg().x() == Approx(45.0));
  CHECK(p.device_angles_deg().z() == Approx(-90.0));
}

TEST_CASE("WitMotion: packets split across reads at every position give the same samples", "[imu]") {
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < 20; ++k) {
    auto c = cycle(k);
    bytes.insert(bytes.end(), c.begin(), c.end());
  }
  for (std::size_t chunk : {1u, 3u, 7u, 10u, 12u, 43u}) {
    DropCounts drops;
    const auto out = parse(bytes, drops, chunk);
    REQUIRE(out.size() == 20);
    for (int k = 0; k < 20; ++k) CHECK(std::lround(out[k].acc_inB.x() / (16.0 * 9.80665 / 32768.0)) == k);
    CHECK(drops.total() == 0);
  }
}

TEST_CASE("WitMotion: garbage between packets loses no valid packet and is counted", "[imu]") {
  FastRng rng(11);
  std::vector<std::uint8_t> bytes;
  std::size_t garbage = 0;
  for (int k = 0; k < 500; ++k) {
    auto c = cycle(k);
    // Random garbage (0x55 headers included, often) before the cycle and between its
    // gyro and angles packets.
    std::size_t before = 0;
    for (int rep = 0; rep < 2; ++rep) {
      const int n = static_cast<int>(rng.uniform() * 14);
      for (int i = 0; i < n; ++i) {
        const std::uint8_t b = rng.uniform() < 0.25 ? 0x55 : static_cast<std::uint8_t>(rng.uniform() * 256);
        c.insert(c.begin() + static_cast<std::ptrdiff_t>(rep == 0 ? 0 : before + 22), b);
        ++garbage;
      }
      if (rep == 0) before = static_cast<std::size_t>(n);
    }
    bytes.insert(bytes.end(), c.begin(), c.end());
  }
  DropCounts drops;
  const auto out = parse(bytes, drops, 64);
  REQUIRE(out.size() == 500);
  for (int k = 0; k < 500; ++k) REQUIRE(std::lround(out[k].acc_inB.x() / (16.0 * 9.80665 / 32768.0)) == k);
  CHECK(drops.count(serial_drop::kSkippedBytes) == garbage);
  CHECK(drops.count(serial_drop::kIncompleteSample) == 0);
}

TEST_CASE("WitMotion: a bad checksum drops that packet's sample, counted, and the stream resyncs", "[imu]") {
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < 10; ++k) {
    auto c = cycle(k);
    if (k == 4) c[11 + 10] ^= 0x01;  // corrupt the gyro packet's checksum
    bytes.insert(bytes.end(), c.begin(), c.end());
  }
  DropCounts drops;
  const auto out = parse(bytes, drops, 1000);
  CHECK(out.size() == 9);
  CHECK(drops.count(serial_drop::kBadChecksum) == 1);
  CHECK(drops.count(serial_drop::kIncompleteSample) == 1);
  CHECK(drops.count(serial_drop::kSkippedBytes) == 11);
}

TEST_CASE("WitMotion: a stream joined mid-cycle, samples back-dated inside a read", "[imu]") {
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < 5; ++k) {
    auto c = cycle(k);
    bytes.insert(bytes.end(), c.begin(), c.end());
  }
  bytes.erase(bytes.begin(), bytes.begin() + 22 + 5);  // join inside the angles packet
  DropCounts drops;
  WitMotionParser p(drops);
  std::vector<ImuSample> out;
  const double byte_ns = 10.0 * 1e9 / 115200.0;
  p.feed(bytes.data(), bytes.size(), 1'000'000'000, byte_ns, out);
  REQUIRE(out.size() == 4);  // the partial first cycle is not a sample, and not counted
  CHECK(drops.count(serial_drop::kIncompleteSample) == 0);
  // The last sample ends with the read; each earlier one 44 bytes of wire time before.
  CHECK(out[3].t == 1'000'000'000);
  CHECK(static_cast<double>(out[3].t - out[2].t) == Approx(44 * byte_ns).margin(1.0));
}
