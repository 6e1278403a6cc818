#include <catch2/catch.hpp>
#include <numbers>
#include <string>

#include "plugins/serial/csv_line_parser.hpp"

using namespace luxloc;

namespace {
std::vector<ImuSample> parse(const std::string& text, DropCounts& drops, const CsvLineOptions& o = {},
                             std::size_t chunk = 1000, TimeNs t = 0) {
  CsvLineParser p(drops, o);
  std::vector<ImuSample> out;
  for (std::size_t i = 0; i < text.size(); i += chunk) {
    const std::string part = text.substr(i, chunk);
    p.feed(reinterpret_cast<const std::uint8_t*>(part.data()), part.size(), t, 0.0, out);
  }
  return out;
}
}  // namespace

TEST_CASE("CSV lines: SPEC order by default, optional magnetometer, CRLF, comments, split reads", "[imu]") {
  const std::string text =
      "# a comment\r\n"
      "0.01,0.1,0.2,9.8,0.01,0.02,0.03,20,1,-40\r\n"
      "0.02,0.1,0.2,9.8,0.01,0.02,0.03\n"
      "0.03 0.1 0.2 9.8 0.01 0.02 0.03 21 2 -41\n";
  for (std::size_t chunk : {1u, 5u, 1000u}) {
    DropCounts drops;
    const auto out = parse(text, drops, {}, chunk);
    REQUIRE(out.size() == 3);
    CHECK(out[0].acc_inB.z() == Approx(9.8));
    CHECK(out[0].gyro_inB.z() == Approx(0.03));
    CHECK(out[0].has_mag);
    CHECK(out[0].mag_inB.z() == Approx(-40));
    CHECK_FALSE(out[1].has_mag);
    CHECK(out[2].mag_inB.x() == Approx(21));
    CHECK(drops.total() == 0);
  }
}

TEST_CASE("CSV lines: a header sets the column order, units convert, bad and long lines are counted", "[imu]") {
  CsvLineOptions o;
  o.acc_to_mps2 = CsvLineOptions::acc_unit("g");
  o.gyro_to_rps = CsvLineOptions::gyro_unit("dps");
  std::string text = "gx;gy;gz;ax;ay;az\n90;0;-180;0;0;1\nhello world\n1;2\n";
  text += std::string(600, '7') + "\n";  // no newline within max_line
  text += "0;0;0;0;1;nan\n0;0;0;1;0;0\n";
  DropCounts drops;
  const auto out = parse(text, drops, o);
  REQUIRE(out.size() == 2);
  CHECK(out[0].gyro_inB.x() == Approx(std::numbers::pi / 2));
  CHECK(out[0].gyro_inB.z() == Approx(-std::numbers::pi));
  CHECK(out[0].acc_inB.z() == Approx(9.80665));
  CHECK(out[1].acc_inB.x() == Approx(9.80665));
  CHECK(drops.count(serial_drop::kBadLine) == 3);  // "hello world", "1;2", the nan
  CHECK(drops.count(serial_drop::kLongLine) == 1);
}

TEST_CASE("CSV lines: configured columns, device time mapped onto the arrival clock", "[imu]") {
  CsvLineOptions o;
  o.columns = CsvLineOptions::parse_columns("_:t:ax:ay:az:gx:gy:gz");
  o.device_time = true;
  o.time_to_s = CsvLineOptions::time_unit("ms");
  DropCounts drops;
  CsvLineParser p(drops, o);
  std::vector<ImuSample> out;
  auto line = [&](const std::string& s, TimeNs arrival) {
    p.feed(reinterpret_cast<const std::uint8_t*>(s.data()), s.size(), arrival, 0.0, out);
  };
  line("7,1000,0,0,9.8,0,0,0\n", 5'000'000'000);   // offset 4 s
  line("7,1010,0,0,9.8,0,0,0\n", 5'012'000'000);   // 2 ms late: offset unchanged
  line("7,1020,0,0,9.8,0,0,0\n", 5'019'000'000);   // less delayed: offset shrinks by 1 ms
  line("7,10,0,0,9.8,0,0,0\n", 5'030'000'000);     // device reset: re-anchored
  REQUIRE(out.size() == 4);
  CHECK(out[0].t == 5'000'000'000);
  CHECK(out[1].t == 5'010'000'000);
  CHECK(out[2].t == 5'019'000'000);
  CHECK(out[3].t == 5'030'000'000);
  // Found by fuzz_csv_imu_line: an absurd device time (1e300 ms) overflowed the ns offset
  // arithmetic; it is a bad line now, and the clock goes on as before.
  line("7,1e300,0,0,9.8,0,0,0\n", 5'040'000'000);
  line("7,-5e15,0,0,9.8,0,0,0\n", 5'041'000'000);
  line("7,40,0,0,9.8,0,0,0\n", 5'060'000'000);
  CHECK(drops.count(serial_drop::kBadLine) == 2);
  REQUIRE(out.size() == 5);
  CHECK(out[4].t == 5'060'000'000);
  CHECK_THROWS_WITH(CsvLineOptions::parse_columns("t:ax:ay:az:gx:gy"), Catch::Contains("missing 'gz'"));
  CHECK_THROWS_WITH(CsvLineOptions::parse_columns("ax:ay:az:gx:gy:gz:mx"), Catch::Contains("mx, my, mz"));
  CHECK_THROWS_WITH(CsvLineOptions::parse_columns("ax:ay:az:gx:gy:gz:q"), Catch::Contains("unknown column 'q'"));
  CHECK_THROWS_AS(CsvLineOptions::mag_unit("tesla"), std::invalid_argument);
  CHECK(CsvLineOptions::mag_unit("gauss") == 100.0);
}
