// `luxloc devices` on this machine (no camera, no serial adapter here) and on an empty
// device folder: exit 0 and a plain "none found".
#include <catch2/catch.hpp>
#include <filesystem>

#include "plugins/v4l2/v4l2_device_info.hpp"
#include "test_support.hpp"

using namespace luxloc;

TEST_CASE("luxloc devices: exit 0, says plainly when no camera or serial port is found", "[v4l2][devices]") {
  const auto empty = test::scratch_dir("devices_empty");
  auto r = test::run_luxloc("devices --dev-dir '" + empty.string() + "'");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("no camera found") && Catch::Contains("no serial port found"));

  // A folder with a serial device name and a non-V4L2 "video" node.
  const auto fake = test::scratch_dir("devices_fake");
  test::write_text(fake / "ttyUSB0", "");
  test::write_text(fake / "video7", "");
  test::write_text(fake / "videoX", "");
  CHECK(v4l2_device_paths(fake.string()) == std::vector<std::string>{(fake / "video7").string()});
  r = test::run_luxloc("devices --dev-dir '" + fake.string() + "'");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("video7: cannot query: not a V4L2 device") &&
                           Catch::Contains("no camera found (no capture device among them)") &&
                           Catch::Contains((fake / "ttyUSB0").string()));

  r = test::run_luxloc("devices");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("Cameras (V4L2") && Catch::Contains("Serial ports"));
  if (v4l2_device_paths().empty()) CHECK_THAT(r.output, Catch::Contains("no camera found"));
}
