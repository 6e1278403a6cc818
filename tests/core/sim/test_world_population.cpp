// The camera and ceiling population of `luxloc sim --world random` and `--camera-mode`
// (issue 12 part 1): draws within the documented ranges, reproducible, lenses that do not
// fold, and LED maps whose frequencies the camera can tell apart.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/sim/scenario.hpp"
#include "core/sim/world_population.hpp"

using namespace luxloc;
using namespace luxloc::sim;

namespace {

// Every frequency of the map inside the band, and distinct classes >= 3 % apart.
void check_frequencies(const Scenario& s, const WorldPlan& plan) {
  std::set<double> f;
  for (const Led& l : s.map.leds()) {
    CHECK(l.freq_hz >= plan.band.f_min_hz * (1.0 - 1e-9));
    CHECK(l.freq_hz <= plan.band.f_max_hz * (1.0 + 1e-9));
    f.insert(l.freq_hz);
  }
  CHECK(static_cast<int>(f.size()) == plan.classes);
  for (auto a = f.begin(), b = std::next(f.begin()); b != f.end(); ++a, ++b) CHECK(*b / *a >= 1.0299);
}

// The ray that lands on the image corner still lies where the radial map grows.
void check_lens_monotonic(const CameraModel& c) {
  const Eigen::Vector3d ray = c.bearing({0.0, 0.0});
  const double r2 = (ray.x() * ray.x() + ray.y() * ray.y()) / (ray.z() * ray.z());
  CHECK(1.0 + 3.0 * c.dist[0] * r2 >= 0.5);
  Eigen::Vector2d uv;
  REQUIRE(c.project(ray, uv));
  CHECK(uv.norm() < 1.0);  // the bearing goes back to the corner
}

}  // namespace

TEST_CASE("parse_camera_mode: WxH:ROW_US:EXPOSURE_US[:HFOV_DEG], errors name the part", "[sim][world]") {
  const CameraMode m = parse_camera_mode("1280x720:45:200:70");
  CHECK(m.width == 1280);
  CHECK(m.height == 720);
  CHECK(m.row_time_s == Approx(45e-6));
  CHECK(m.exposure_s == Approx(200e-6));
  CHECK(m.hfov_deg == 70.0);
  CHECK(parse_camera_mode("640x480:30:100").hfov_deg == Approx(69.6));
  const auto fails = [](const char* text, const char* says) {
    INFO(text);
    CHECK_THROWS_WITH(parse_camera_mode(text), Catch::Contains(says));
  };
  fails("1280x720:45", "WxH:ROW_US:EXPOSURE_US");
  fails("1280*720:45:200", "size");
  fails("1280x72.5:45:200", "size");
  fails("1280x720:0.5:200", "row time");
  fails("1280x720:45us:200", "row time");
  fails("1280x720:45:0", "exposure");
  fails("1280x720:45:200:150", "field of view");
}

TEST_CASE("camera_for_mode: f from the field of view, centred, a lens that does not fold", "[sim][world]") {
  for (const char* text : {"640x480:30:100:50", "1280x720:45:200:70", "800x600:15:300:95", "1920x1080:20:50:95"}) {
    INFO(text);
    const CameraMode m = parse_camera_mode(text);
    const CameraModel c = camera_for_mode(m);
    CHECK(c.width == m.width);
    CHECK(2.0 * std::atan(0.5 * c.width / c.fx) * 180.0 / 3.14159265358979 == Approx(m.hfov_deg));
    CHECK(c.cx == 0.5 * m.width);
    CHECK(c.row_time_s == m.row_time_s);
    CHECK(c.dist[0] < 0.0);
    check_lens_monotonic(c);
  }
}

TEST_CASE("draw_world: issue 12's ranges, reproducible per seed, rows read within the frame", "[sim][world]") {
  std::set<int> widths;
  std::set<std::string> layouts;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    INFO("seed " << seed);
    const WorldDraw w = draw_world(seed, 30.0);
    widths.insert(w.camera.width);
    layouts.insert(w.layout);
    CHECK(w.camera.row_time_s >= 15e-6);
    CHECK(w.camera.row_time_s <= 45e-6);
    CHECK(w.camera.row_time_s * w.camera.height <= 0.9 / 30.0 + 1e-12);
    CHECK(w.camera.exposure_s >= 50e-6);
    CHECK(w.camera.exposure_s <= 300e-6);
    CHECK(w.camera.hfov_deg >= 50.0);
    CHECK(w.camera.hfov_deg <= 95.0);
    CHECK(w.spacing_m >= 2.0);
    CHECK(w.spacing_m <= 4.0);
    CHECK(w.ceiling_m >= 2.4);
    CHECK(w.ceiling_m <= 4.0);
    const WorldDraw again = draw_world(seed, 30.0);
    CHECK(again.camera.row_time_s == w.camera.row_time_s);
    CHECK(again.spacing_m == w.spacing_m);
  }
  CHECK(widths == std::set<int>{640, 800, 1280, 1920});
  CHECK(layouts == std::set<std::string>{"grid", "irregular"});
}

TEST_CASE("apply_world: lights over the room at the drawn ceiling, frequencies the camera separates", "[sim][world]") {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    INFO("seed " << seed);
    Scenario s = make_scenario("walk");
    const WorldDraw w = draw_world(seed, 30.0);
    const WorldPlan plan = apply_world(s, w, seed);
    REQUIRE(s.map.size() == static_cast<std::size_t>(plan.leds));
    CHECK(plan.leds >= 2);
    for (const Led& l : s.map.leds()) {
      CHECK(l.p_inW.z() == w.ceiling_m);
      CHECK(l.p_inW.x() >= 0.3 - 1e-9);
      CHECK(l.p_inW.x() <= s.room_x_m - 0.3 + 1e-9);
      CHECK(l.p_inW.y() >= 0.3 - 1e-9);
      CHECK(l.p_inW.y() <= s.room_y_m - 0.3 + 1e-9);
      CHECK(l.diameter_m == plan.led_diameter_m);
    }
    CHECK(plan.led_diameter_m >= w.led_diameter_m);
    CHECK(plan.led_diameter_m <= 0.6);
    CHECK(s.camera.exposure_s == plan.exposure_s);
    CHECK(plan.exposure_s <= w.camera.exposure_s);
    check_frequencies(s, plan);
    check_lens_monotonic(s.camera);
  }
}

TEST_CASE("apply_camera_mode: the scenario's lights, frequencies re-planned for the mode", "[sim][world]") {
  Scenario s = make_scenario("walk");
  const Scenario before = make_scenario("walk");
  const WorldPlan plan = apply_camera_mode(s, parse_camera_mode("1280x720:45:200:70"), 1);
  REQUIRE(s.map.size() == before.map.size());
  for (std::size_t i = 0; i < s.map.size(); ++i) CHECK(s.map.leds()[i].p_inW == before.map.leds()[i].p_inW);
  CHECK(s.camera.width == 1280);
  // 200 us exposure: f T <= 0.6 keeps half the stripe contrast, so nothing above 3 kHz
  // (the default map reaches 4.3 kHz, which this exposure would wash out).
  CHECK(plan.band.f_max_hz == Approx(3000.0).epsilon(0.01));
  CHECK(plan.band.high_limit == "contrast");
  CHECK(plan.classes == 12);
  check_frequencies(s, plan);

  Scenario floor = make_scenario("floor");
  CHECK_THROWS_WITH(apply_camera_mode(floor, CameraMode{}, 1), Catch::Contains("no up-looking camera"));
  Scenario uwb = make_scenario("uwb");
  CHECK_THROWS_AS(apply_world(uwb, draw_world(1, 30.0), 1), std::invalid_argument);
}
