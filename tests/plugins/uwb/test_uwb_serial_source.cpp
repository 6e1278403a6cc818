// The `uwb:` source through a socat pseudo-terminal pair with real byte streams.
#include <catch2/catch.hpp>
#include <atomic>
#include <chrono>
#include <thread>

#include "core/common/input_error.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/uwb/uwb_serial_source.hpp"
#include "../serial/socat_pair.hpp"
#include "../source_reader.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace std::chrono_literals;

namespace {

#define REQUIRE_SOCAT()                                               \
  if (!test::SocatPair::available()) {                                \
    WARN("socat not installed: UWB pseudo-terminal test skipped");    \
    return;                                                           \
  }

std::string lec_line(int k) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "DIST,3,AN0,0C8E,0.00,0.00,2.50,%.2f,AN1,1A9C,8.00,0.00,2.40,%.2f,AN2,2B01,4.00,6.00,2.60,%.2f,"
                "POS,3.10,2.20,1.00,%d\r\n",
                1.0 + 0.01 * k, 2.0 + 0.01 * k, 3.0 + 0.01 * k, 40 + k % 60);
  return buf;
}

}  // namespace

TEST_CASE("UWB DWM1001 source: 300 lec lines with broken ones and split writes through a pty", "[uwb]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("uwb_dwm1001"));
  REQUIRE(pty.running());
  SourcePtr source = make_live_source(SourceSpec::parse("uwb:" + pty.b() + ",baud=115200,protocol=dwm1001"));
  REQUIRE(source->live());
  SerialPort writer(pty.a(), 115200);
  constexpr int kLines = 300;
  int broken = 0;
  std::string text = "dwm> lec\r\n";
  for (int k = 0; k < kLines; ++k) {
    if (k % 25 == 7) {  // a report cut by the next one (what the tag does at high rates)
      text += lec_line(k).substr(0, 30 + k % 40);
      ++broken;
    }
    text += lec_line(k);
  }
  // An interleaved report spoils the line it runs into: both are lost.
  const std::size_t expected = 3 * static_cast<std::size_t>(kLines - broken);
  test::SourceReader<> reader(*source, expected);
  // Writes of odd sizes that split lines anywhere, paced like a 100 Hz tag.
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = std::min<std::size_t>(text.size() - i, 97);
    writer.write_all(reinterpret_cast<const std::uint8_t*>(text.data() + i), n);
    i += n;
    std::this_thread::sleep_for(1ms);
  }
  REQUIRE(reader.join_within(5s));
  REQUIRE(reader.samples.size() == expected);  // every intact line, no range lost
  std::size_t i = 0;
  for (int k = 0; k < kLines; ++k) {
    if (k % 25 == 7) continue;  // the line the broken report ran into
    const auto& a1 = std::get<UwbSample>(reader.samples[i + 1]);
    REQUIRE(a1.anchor == 0x1A9C);
    REQUIRE(a1.range_m == Approx(2.0 + 0.01 * k));
    REQUIRE(a1.p_AinW.isApprox(Eigen::Vector3d(8.0, 0.0, 2.4)));
    if (i > 0) REQUIRE(a1.t >= std::get<UwbSample>(reader.samples[i - 2]).t);
    i += 3;
  }
  CHECK(source->drops().count(uwb_drop::kBadLine) == static_cast<std::uint64_t>(broken));
  CHECK(source->failure().empty());
}

TEST_CASE("UWB source: TOF+AOA records, the device vanishing, bad specs", "[uwb]") {
  REQUIRE_SOCAT();
  test::SocatPair pty(test::scratch_dir("uwb_tof_aoa"));
  REQUIRE(pty.running());
  UwbSerialOptions o = UwbSerialOptions::from_spec(SourceSpec::parse("uwb:" + pty.b() + ",protocol=tof-aoa"));
  o.report_to_stderr = false;
  UwbSerialSource source(o);
  test::SourceReader<> reader(source, 1000);
  {
    SerialPort writer(pty.a(), 115200);
    const std::string text = "1,3.25,0.50\n1,3.30\ngarbage\n1,3.35,0.52\n";
    writer.write_all(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
    std::this_thread::sleep_for(150ms);
  }
  pty.stop();  // unplugged
  REQUIRE(reader.join_within(3s));
  REQUIRE(reader.samples.size() == 3);
  CHECK(std::get<UwbSample>(reader.samples[2]).aoa_rad == Approx(0.52));
  CHECK(source.drops().count(uwb_drop::kBadLine) == 1);
  CHECK_THAT(source.failure(), Catch::Contains("device lost"));

  CHECK_THROWS_AS(UwbSerialOptions::from_spec(SourceSpec::parse("uwb:/dev/null,protocol=nmea")), InputError);
  CHECK_THROWS_AS(UwbSerialOptions::from_spec(SourceSpec::parse("uwb:/dev/null,baud=12345")), InputError);
  CHECK_THROWS_AS(UwbSerialOptions::from_spec(SourceSpec::parse("uwb:/dev/null,colour=red")), InputError);
  CHECK_THROWS(make_live_source(SourceSpec::parse("uwb:/nonexistent/tty")));
}
