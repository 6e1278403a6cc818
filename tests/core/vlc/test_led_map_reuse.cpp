// Frequency reuse in the LED map (issue 14): classes of copies, the rule between copies and
// distinct frequencies, the class match, the spatial index and the co-visibility check.
#include <catch2/catch.hpp>

#include <random>

#include "core/common/input_error.hpp"
#include "core/sim/scenario.hpp"
#include "core/vlc/led_class_index.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_visibility.hpp"

using namespace luxloc;

namespace {
Led led(int id, double f, double x, double y) {
  Led l;
  l.id = id;
  l.freq_hz = f;
  l.p_inW = {x, y, 3.0};
  return l;
}
}  // namespace

TEST_CASE("LED map: equal frequencies form one class, distinct ones 2 % apart, anything between is refused", "[vlc][reuse]") {
  const LedMap m({led(1, 1000, 0, 0), led(2, 1300, 2, 0), led(3, 1000.4, 10, 0), led(4, 1300, 12, 0), led(5, 1600, 4, 0)},
                 "m.yaml");
  REQUIRE(m.classes().size() == 3);
  CHECK(m.reuses_frequencies());
  CHECK(m.class_of(0) == m.class_of(2));
  CHECK(m.class_of(1) == m.class_of(3));
  CHECK(m.class_of(4) != m.class_of(0));
  CHECK(m.min_reuse_distance_m() == Approx(10.0));
  CHECK(m.min_relative_separation() == Approx(0.23).epsilon(0.01));
  // A reused class matches without naming the LED; a class of one names it.
  const auto a = m.match_frequency(1001.0, 0.01);
  CHECK(a.klass == m.class_of(0));
  CHECK(a.index == -1);
  const auto b = m.match_frequency(1590.0, 0.01);
  CHECK(b.index == 4);
  CHECK(m.match_frequency(1150.0, 0.01).klass == -1);
  // 0.5 % apart: neither a copy (0.1 %) nor separable (2 %).
  try {
    LedMap({led(1, 1000, 0, 0), led(2, 1005, 9, 0)}, "bad.yaml");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("bad.yaml") && Catch::Contains("freq_hz") && Catch::Contains("LED id 2"));
  }
  // A map without reuse keeps one class per LED.
  const LedMap room = sim::default_led_grid();
  CHECK(room.classes().size() == room.size());
  CHECK_FALSE(room.reuses_frequencies());
  for (std::size_t i = 0; i < room.size(); ++i) CHECK(room.match_frequency(room.leds()[i].freq_hz, 0.01).index == static_cast<int>(i));
}

TEST_CASE("LED class index: nearest copy and LEDs within a radius agree with brute force on 5000 LEDs", "[vlc][reuse]") {
  std::mt19937_64 rng(14);
  std::vector<Led> leds;
  // 100 x 50 grid, 2 m apart, 12 classes in a 4 x 3 tile with a random shift per row block.
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 100; ++i) leds.push_back(led(j * 100 + i + 1, 1000 + 300 * ((i % 4) + 4 * (j % 3)), 2.0 * i, 2.0 * j));
  const LedMap map(std::move(leds), "grid");
  REQUIRE(map.size() == 5000);
  REQUIRE(map.classes().size() == 12);
  const LedClassIndex index(map);
  CHECK(index.memory_bytes() < 10u * 1024 * 1024);
  std::uniform_real_distribution<double> ux(-5, 205), uy(-5, 105);
  int found = 0;
  for (int q = 0; q < 2000; ++q) {
    const double x = ux(rng), y = uy(rng);
    const int k = static_cast<int>(q % 12);
    const double r = index.capture_radius(k);
    int best = -1;
    double bd = r;
    for (int i : map.classes()[static_cast<std::size_t>(k)].members) {
      const double d = (map.leds()[static_cast<std::size_t>(i)].p_inW.head<2>() - Eigen::Vector2d(x, y)).norm();
      if (d <= bd) {
        bd = d;
        best = i;
      }
    }
    CHECK(index.nearest(k, x, y, r) == best);
    found += best >= 0;
    std::vector<int> got;
    index.within(x, y, 3.0, got);
    std::size_t expect = 0;
    for (const Led& l : map.leds()) expect += (l.p_inW.head<2>() - Eigen::Vector2d(x, y)).norm() <= 3.0;
    CHECK(got.size() == expect);
  }
  CHECK(found > 500);  // the queries do find copies (the test is not vacuous)
  CHECK(index.nearest(0, std::numeric_limits<double>::quiet_NaN(), 0, 3) == -1);
  CHECK(index.nearest(0, 1e300, -1e300, 3) == -1);
}

TEST_CASE("Frequency reuse: two copies a level camera sees together are refused, copies beyond its view are fine", "[vlc][reuse]") {
  const CameraModel cam = sim::default_sim_camera();
  // 2 m above the camera the 640 x 480 image at f 460 spans ~2.8 m x 2.1 m: 3.5 m diagonal.
  const double d = co_visibility_distance_m(cam, 2.0, 0.0);
  CHECK(d == Approx(2.0 * 2.0 * std::hypot(320.0, 240.0) / 460.0).epsilon(0.06));  // k1 < 0 widens the corners a little
  CHECK(co_visibility_distance_m(cam, 2.0, 0.26) > d);
  const LedMap near({led(1, 1000, 0, 0), led(2, 1000, 3.0, 0), led(3, 1600, 1.5, 0)}, "near.yaml");
  try {
    check_frequency_reuse(near, cam, 1.0, "near.yaml");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("near.yaml") && Catch::Contains("LED id 1") && Catch::Contains("LED id 2"));
  }
  const LedMap far({led(1, 1000, 0, 0), led(2, 1000, 6.0, 0), led(3, 1600, 3, 0)}, "far.yaml");
  CHECK_NOTHROW(check_frequency_reuse(far, cam, 1.0, "far.yaml"));
}

// fuzz_session found it: an LED at x = 1.7e31 m overflowed the index's cell arithmetic (UB),
// and LEDs 100 km apart in 2 m cells would have asked for 1e10 cells.
TEST_CASE("LED map: a position beyond 100 km is refused, a map 180 km wide keeps a small exact index", "[vlc][reuse]") {
  try {
    LedMap({led(1, 1000, 0, 0), led(2, 1300, 1.7e31, 0)}, "far.yaml");
    FAIL("accepted");
  } catch (const luxloc::InputError& e) {
    CHECK(std::string(e.what()).find("far.yaml") != std::string::npos);
    CHECK(std::string(e.what()).find("LED #2") != std::string::npos);
    CHECK(std::string(e.what()).find("100 km") != std::string::npos);
  }
  // Two same-class pairs at the far corners and one in the middle.
  const LedMap map({led(1, 1000, -9e4, -9e4), led(2, 1000, 9e4, 9e4), led(3, 1300, 0, 0), led(4, 1300, 4, 0),
                    led(5, 1600, -9e4 + 2, -9e4)},
                   "wide");
  const LedClassIndex index(map);
  CHECK(index.memory_bytes() < 64u * 1024 * 1024);
  const int far_class = map.class_of(0);
  CHECK(index.nearest(far_class, -9e4 + 1, -9e4, 10.0) == 0);
  CHECK(index.nearest(far_class, 9e4 - 1, 9e4, 10.0) == 1);
  std::vector<int> got;
  index.within(-9e4 + 1, -9e4, 3.0, got);
  std::sort(got.begin(), got.end());
  CHECK(got == std::vector<int>{0, 4});
}
