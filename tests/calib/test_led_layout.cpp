// Light layouts for `calib ledmap plan` (calib/led_layout.hpp): CSV (x,y[,z][,id]), a YAML
// LED map whose frequencies are ignored, a grid spec; every bad input an InputError naming
// the file, the line and the field.
#include <catch2/catch.hpp>

#include <string>
#include <unistd.h>

#include "calib/led_layout.hpp"
#include "core/common/input_error.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

std::filesystem::path layout_dir(const std::string& name) {
  return test::scratch_dir("led_layout_" + name + "_" + std::to_string(::getpid()));
}

// The InputError read_led_layout throws for `text` written to dir/name.
InputError layout_error(const std::filesystem::path& dir, const std::string& name, const std::string& text,
                        std::optional<double> ceiling = 3.0) {
  const auto p = dir / name;
  test::write_text(p, text);
  try {
    read_led_layout(p.string(), ceiling);
  } catch (const InputError& e) {
    return e;
  }
  FAIL("no InputError for " << name);
  return InputError("", 0, "", "");
}

}  // namespace

TEST_CASE("LED layout CSV: x,y at the ceiling height, ids 1..n, comments skipped", "[calib][plan]") {
  const auto dir = layout_dir("csv_xy");
  test::write_text(dir / "l.csv", "# office, level 2\nx,y\n1.0,2.0\n\n# second row\n3.5,2.0\n  6, 2.25 \n");
  const LedLayout l = read_led_layout((dir / "l.csv").string(), 2.8);
  REQUIRE(l.leds.size() == 3);
  CHECK_FALSE(l.ids_given);
  CHECK(l.leds[0].id == 1);
  CHECK(l.leds[2].id == 3);
  CHECK(l.leds[2].p_inW.x() == 6.0);
  CHECK(l.leds[2].p_inW.y() == 2.25);
  for (const Led& led : l.leds) CHECK(led.p_inW.z() == 2.8);
  CHECK(l.max_z == 2.8);
  CHECK(l.origin == (dir / "l.csv").string());
}

TEST_CASE("LED layout CSV: z and id columns kept, an empty z takes the ceiling height", "[calib][plan]") {
  const auto dir = layout_dir("csv_xyz");
  test::write_text(dir / "l.csv", "id,x,y,z\n17,0,0,3.1\n4,2.5,0,\n9,5,0,2.9\n");
  const LedLayout l = read_led_layout((dir / "l.csv").string(), 3.0);
  REQUIRE(l.leds.size() == 3);
  CHECK(l.ids_given);
  CHECK(l.leds[0].id == 17);
  CHECK(l.leds[1].id == 4);
  CHECK(l.leds[2].id == 9);
  CHECK(l.leds[0].p_inW.z() == 3.1);
  CHECK(l.leds[1].p_inW.z() == 3.0);
  CHECK(l.max_z == 3.1);
  // Without a ceiling height, a row without z is refused, naming it.
  const InputError e = layout_error(dir, "l2.csv", "x,y,z\n0,0,3\n1,0,\n", std::nullopt);
  CHECK(e.line() == 3);
  CHECK(e.field() == "z");
}

TEST_CASE("LED layout CSV errors: bad number (line, field), no header, no z, duplicate id", "[calib][plan]") {
  const auto dir = layout_dir("csv_errors");
  {
    const InputError e = layout_error(dir, "bad.csv", "x,y\n1,1\n2,1O\n3,1\n");
    CHECK(e.line() == 3);
    CHECK(e.field() == "y");
    CHECK(std::string(e.what()).find("bad.csv:3: field 'y'") != std::string::npos);
  }
  {
    const InputError e = layout_error(dir, "nohdr.csv", "1.0,2.0\n3.0,2.0\n");
    CHECK(e.line() == 1);
    CHECK(e.field() == "x");
    CHECK(std::string(e.what()).find("no header row") != std::string::npos);
  }
  {
    const InputError e = layout_error(dir, "noy.csv", "x,z\n1,3\n");
    CHECK(e.field() == "y");
  }
  {
    const InputError e = layout_error(dir, "noz.csv", "x,y\n1,3\n", std::nullopt);
    CHECK(e.line() == 2);
    CHECK(e.field() == "z");
    CHECK(std::string(e.what()).find("--ceiling-height") != std::string::npos);
  }
  {
    const InputError e = layout_error(dir, "dup.csv", "id,x,y\n1,0,0\n2,1,0\n1,2,0\n");
    CHECK(e.line() == 4);
    CHECK(e.field() == "id");
  }
  {
    const InputError e = layout_error(dir, "empty.csv", "x,y\n# nothing\n");
    CHECK(std::string(e.what()).find("no LED") != std::string::npos);
  }
  {
    const InputError e = layout_error(dir, "layout.txt", "x,y\n1,1\n");
    CHECK(e.field() == "--layout");
  }
  {
    const InputError e = layout_error(dir, "far.csv", "x,y\n1,1\n2,-3e6\n");  // 3000 km: not metres
    CHECK(e.line() == 3);
    CHECK(e.field() == "y");
  }
}

TEST_CASE("LED layout YAML: ids, positions and light fields kept, frequencies ignored", "[calib][plan]") {
  const auto dir = layout_dir("yaml");
  // Repeated, too close and missing frequencies: a map LedMap::load would refuse.
  test::write_text(dir / "m.yaml",
                   "%YAML:1.0\n---\nleds:\n"
                   "   - { id: 7, freq_hz: 2500., x: 1.0, y: 2.0, z: 3.0, duty: 0.4 }\n"
                   "   - { id: 3, freq_hz: 2500., x: 4.0, y: 2.0, z: 3.2 }\n"
                   "   - { id: 12, freq_hz: 2510., x: 7.0, y: 2.0 }\n"
                   "   - { id: 20, x: 10.0, y: 2.0, z: 3.0, power: 2.0 }\n");
  const LedLayout l = read_led_layout((dir / "m.yaml").string(), 2.9);
  REQUIRE(l.leds.size() == 4);
  CHECK(l.ids_given);
  CHECK(l.leds[0].id == 7);
  CHECK(l.leds[1].id == 3);
  CHECK(l.leds[2].id == 12);
  CHECK(l.leds[3].id == 20);
  CHECK(l.leds[0].duty == 0.4);
  CHECK(l.leds[3].power == 2.0);
  CHECK(l.leds[2].p_inW.z() == 2.9);  // no z: the ceiling height
  CHECK(l.max_z == 3.2);
  for (const Led& led : l.leds) CHECK(led.freq_hz == 0.0);

  const InputError dup = layout_error(dir, "dup.yaml",
                                      "%YAML:1.0\n---\nleds:\n   - { id: 1, x: 0, y: 0, z: 3 }\n"
                                      "   - { id: 1, x: 3, y: 0, z: 3 }\n");
  CHECK(dup.field() == "id");
  CHECK(std::string(dup.what()).find("LED #2") != std::string::npos);
  const InputError nox =
      layout_error(dir, "nox.yaml", "%YAML:1.0\n---\nleds:\n   - { id: 1, y: 0, z: 3 }\n");
  CHECK(nox.field() == "x");
  const InputError noz =
      layout_error(dir, "noz.yaml", "%YAML:1.0\n---\nleds:\n   - { id: 1, x: 0, y: 0 }\n", std::nullopt);
  CHECK(noz.field() == "z");
}

TEST_CASE("LED layout grid: inclusive ranges, ids row by row, bad specs named", "[calib][plan]") {
  const LedLayout g = grid_led_layout("1.25:58.75:2.5,1.25:28.75:2.5", 3.0);
  REQUIRE(g.leds.size() == 24u * 12u);
  CHECK(g.leds.front().id == 1);
  CHECK(g.leds.back().id == 288);
  CHECK(g.leds.back().p_inW.x() == Approx(58.75));
  CHECK(g.leds.back().p_inW.y() == Approx(28.75));
  CHECK(g.leds[1].p_inW.x() == Approx(3.75));  // x first, then rows in y
  CHECK(g.leds[24].p_inW.y() == Approx(3.75));
  CHECK(g.max_z == 3.0);
  CHECK(grid_led_layout("0:0.3:0.1,0:0:1", 3.0).leds.size() == 4);  // 0.3 / 0.1 rounds to 2.999..: inclusive
  for (const char* bad : {"1:2:1", "1:2,1:2:1", "1:2:1,1:2:1,1:2:1", "a:2:1,1:2:1", "1:2:0,1:2:1", "2:1:1,1:2:1",
                          "1:2:1,1:2:-1", "0:1000:0.0001,0:1000:0.0001", "1:2:1:3,1:2:1", "", "1:2:1,"}) {
    INFO(bad);
    try {
      grid_led_layout(bad, 3.0);
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.field() == "--grid");
      CHECK(e.file() == "--grid");
    }
  }
  CHECK_THROWS_AS(grid_led_layout("0:10:2.5,0:10:2.5", std::nullopt), InputError);
}

TEST_CASE("LED layout density: the most LEDs within half the conflict distance of one (a class bound)",
          "[calib][plan]") {
  // 2.5 m grid: a 4.58 m conflict distance (half 2.29 m) holds one LED; 5.2 m (2.6 m) the
  // centre and its 4 neighbours (at 2.5 m; the diagonals at 3.54 m are out).
  const LedLayout g = grid_led_layout("0:20:2.5,0:20:2.5", 3.0);
  CHECK(densest_cluster(g, 4.58).leds_within == 1);
  const LayoutDensity d = densest_cluster(g, 5.2);
  CHECK(d.leds_within == 5);
  REQUIRE(d.centre >= 0);
  const Led& c = g.leds[static_cast<std::size_t>(d.centre)];
  CHECK((c.p_inW.x() > 0.0 && c.p_inW.x() < 20.0 && c.p_inW.y() > 0.0 && c.p_inW.y() < 20.0));  // not an edge LED
  // A cluster of 7 (with a repeated position) in a sparse layout spread over 100 km.
  LedLayout l;
  for (int i = 0; i < 6; ++i) {
    Led led;
    led.p_inW = {50000.0 + 0.3 * i, -20000.0, 3.0};
    l.leds.push_back(led);
  }
  l.leds.push_back(l.leds.back());
  Led far;
  far.p_inW = {-50000.0, 30000.0, 3.0};
  l.leds.push_back(far);
  CHECK(densest_cluster(l, 4.0).leds_within == 7);
  CHECK(densest_cluster(l, 0.1).leds_within == 2);  // only the repeated position
  CHECK(densest_cluster(LedLayout{}, 4.0).leds_within == 0);
}
