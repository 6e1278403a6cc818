// LED map files: the optional diameter_m (SPEC.md) is known only where given; the camera's
// disc height (core/vlc/camera_height.hpp) uses it only then.
#include <catch2/catch.hpp>
#include <string>

#include "core/common/input_error.hpp"
#include "core/vlc/led_map.hpp"
#include "test_support.hpp"

using namespace luxloc;

TEST_CASE("LED map: diameter_m is known only where the file gives it, and kept so on save", "[vlc][ledmap]") {
  const auto dir = test::scratch_dir("led_map_diameter");
  const auto path = dir / "ledmap.yaml";
  test::write_text(path, "%YAML:1.0\n---\nleds:\n"
                         "  - { id: 1, freq_hz: 1000, x: 1.0, y: 1.0, z: 3.0, diameter_m: 0.25 }\n"
                         "  - { id: 2, freq_hz: 1500, x: 3.0, y: 1.0, z: 3.0 }\n");
  const LedMap map = LedMap::load(path.string());
  REQUIRE(map.size() == 2);
  CHECK(map.leds()[0].diameter_known);
  CHECK(map.leds()[0].diameter_m == Approx(0.25));
  CHECK_FALSE(map.leds()[1].diameter_known);
  // A placeholder is not written back as if measured.
  const auto saved = dir / "saved.yaml";
  map.save(saved.string());
  const LedMap again = LedMap::load(saved.string());
  CHECK(again.leds()[0].diameter_known);
  CHECK(again.leds()[0].diameter_m == Approx(0.25));
  CHECK_FALSE(again.leds()[1].diameter_known);
}

TEST_CASE("LED map: an impossible diameter_m is refused, naming the LED and the field", "[vlc][ledmap]") {
  const auto dir = test::scratch_dir("led_map_diameter_bad");
  const auto path = dir / "ledmap.yaml";
  for (const std::string bad : {"-0.2", "0", "12"}) {
    test::write_text(path, "%YAML:1.0\n---\nleds:\n  - { id: 7, freq_hz: 1000, x: 1.0, y: 1.0, z: 3.0, diameter_m: " +
                               bad + " }\n");
    INFO(bad);
    try {
      (void)LedMap::load(path.string());
      FAIL("accepted diameter_m " << bad);
    } catch (const InputError& e) {
      CHECK(e.field() == "diameter_m");
      CHECK(std::string(e.what()).find("7") != std::string::npos);
    }
  }
}
