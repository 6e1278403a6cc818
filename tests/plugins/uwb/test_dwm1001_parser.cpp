// DWM1001 `lec` lines and TOF+AOA records: parsing, broken lines, drop counts.
#include <catch2/catch.hpp>
#include <string>

#include "plugins/uwb/dwm1001_parser.hpp"
#include "plugins/uwb/tof_aoa_line_parser.hpp"

using namespace luxloc;

namespace {

std::vector<SensorData> feed(UwbStreamParser& p, const std::string& text, std::size_t chunk = 7) {
  std::vector<SensorData> out;
  for (std::size_t i = 0; i < text.size(); i += chunk) {
    const std::size_t n = std::min(chunk, text.size() - i);
    p.feed(reinterpret_cast<const std::uint8_t*>(text.data() + i), n, static_cast<TimeNs>(i + n) * 1000, 1000.0, out);
  }
  return out;
}

const std::string kLine =
    "DIST,4,AN0,022E,7.94,8.03,0.00,3.44,AN1,9280,7.95,0.00,0.00,5.68,AN2,DCAE,0.00,8.03,0.00,7.76,AN3,5431,0.00,"
    "0.00,0.00,8.73,POS,6.95,5.37,-1.97,52\r\n";

}  // namespace

TEST_CASE("DWM1001 lec: ranges with anchor positions, hex ids, the POS block as an optional fix", "[uwb]") {
  DropCounts drops;
  Dwm1001Options o;
  o.emit_position = true;
  Dwm1001Parser p(drops, o);
  const auto out = feed(p, "dwm> lec\r\n" + kLine);
  REQUIRE(out.size() == 5);
  const auto& a0 = std::get<UwbSample>(out[0]);
  CHECK(a0.anchor == 0x022E);
  CHECK(a0.range_m == Approx(3.44));
  CHECK(a0.p_AinW.isApprox(Eigen::Vector3d(7.94, 8.03, 0.0)));
  CHECK(std::isnan(a0.aoa_rad));
  CHECK(std::get<UwbSample>(out[3]).anchor == 0x5431);
  // All ranges of one line share the arrival time of its newline.
  CHECK(std::get<UwbSample>(out[3]).t == a0.t);
  CHECK(a0.t == static_cast<TimeNs>(10 + kLine.size()) * 1000);  // "dwm> lec\r\n" is 10 bytes
  const auto& pos = std::get<FixSample>(out[4]);
  CHECK(pos.p_inW.x() == Approx(6.95));
  CHECK(drops.total() == 0);
}

TEST_CASE("DWM1001 lec: broken and interleaved lines are dropped whole and counted", "[uwb]") {
  DropCounts drops;
  Dwm1001Parser p(drops);  // ranges only
  std::string text;
  text += kLine;
  text += kLine.substr(0, 40) + "\r\n";                  // cut short
  text += kLine.substr(0, 60) + kLine;                   // two reports interleaved (no newline between)
  text += "DIST,2,AN0,022E,7.94,8.03,0.00,abc,AN1,9280,7.95,0.00,0.00,5.68\n";  // not a number
  text += "DIST,1,AN0,022E,7.94,8.03,0.00,3.44\n";      // no POS: fine
  text += "DIST,1,AN0,022E,7.94,8.03,0.00,3.44,POS,nan,nan,nan,0\n";  // tag without a solution
  text += "POS,1.0,2.0,0.5,80\n";                        // lep line: ranges only -> nothing
  text += "\x01\x02garbage\n";
  text += "DIST,1,AN0,022E,7.94,8.03,0.00,-1.00\n";      // negative range
  const auto out = feed(p, text, 13);
  // 4 + 1 + 1 ranges from the good lines.
  REQUIRE(out.size() == 6);
  for (const SensorData& d : out) CHECK(std::holds_alternative<UwbSample>(d));
  CHECK(drops.count(uwb_drop::kBadLine) == 4);
  CHECK(drops.count(uwb_drop::kBadPosition) == 1);
  CHECK(p.records() == 4);
}

TEST_CASE("TOF+AOA records: anchor,range[,aoa] lines", "[uwb]") {
  DropCounts drops;
  TofAoaLineParser p(drops);
  const auto out = feed(p, "# base station\nanchor,range_m,aoa_rad\n1,3.25,0.5\n2,4.0\n1,x,0.2\n1,2.0,0.1,9\n");
  REQUIRE(out.size() == 2);
  CHECK(std::get<UwbSample>(out[0]).aoa_rad == Approx(0.5));
  CHECK(std::isnan(std::get<UwbSample>(out[1]).aoa_rad));
  CHECK(drops.count(uwb_drop::kBadLine) == 2);
}
