// The V4L2 source without a camera: spec parsing and its errors, the exposure unit
// conversion and control names, and the clear errors for a missing or non-V4L2 device.
#include <catch2/catch.hpp>
#include <filesystem>

#include "core/common/input_error.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/v4l2/exposure_control.hpp"
#include "plugins/v4l2/v4l2_camera_source.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

std::string input_error_field(const std::string& spec) {
  try {
    (void)v4l2_options_from_spec(SourceSpec::parse(spec));
  } catch (const InputError& e) {
    return e.field();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("v4l2 spec: defaults, every option, and errors naming the key", "[v4l2]") {
  V4l2CameraOptions o = v4l2_options_from_spec(SourceSpec::parse("v4l2:/dev/video2"));
  CHECK(o.path == "/dev/video2");
  CHECK(o.width == 640);
  CHECK(o.height == 480);
  CHECK(o.fps == 30.0);
  REQUIRE(o.exposure_us.has_value());
  CHECK(*o.exposure_us == 100.0);
  CHECK_FALSE(o.gain.has_value());
  CHECK_FALSE(o.format.has_value());

  o = v4l2_options_from_spec(
      SourceSpec::parse("v4l2:/dev/video0,width=1280,height=720,fps=60,exposure_us=300,gain=8,format=mjpeg"));
  CHECK(o.width == 1280);
  CHECK(o.height == 720);
  CHECK(o.fps == 60.0);
  CHECK(*o.exposure_us == 300.0);
  CHECK(*o.gain == 8.0);
  CHECK(*o.format == PixelFormat::mjpeg);
  CHECK_FALSE(v4l2_options_from_spec(SourceSpec::parse("v4l2:/dev/video0,exposure_us=auto")).exposure_us.has_value());
  CHECK(*v4l2_options_from_spec(SourceSpec::parse("v4l2:/dev/video0,format=grey")).format == PixelFormat::grey);
  CHECK_FALSE(o.row_time_us.has_value());
  CHECK(*v4l2_options_from_spec(SourceSpec::parse("v4l2:/dev/video0,row_time_us=14.565")).row_time_us == 14.565);

  CHECK(input_error_field("v4l2:/dev/video0,width=abc") == "width");
  CHECK(input_error_field("v4l2:/dev/video0,width=-3") == "width");
  CHECK(input_error_field("v4l2:/dev/video0,height=12.5") == "height");
  CHECK(input_error_field("v4l2:/dev/video0,fps=0") == "fps");
  CHECK(input_error_field("v4l2:/dev/video0,exposure_us=0") == "exposure_us");
  CHECK(input_error_field("v4l2:/dev/video0,exposure_us=fast") == "exposure_us");
  CHECK(input_error_field("v4l2:/dev/video0,gain=-1") == "gain");
  CHECK(input_error_field("v4l2:/dev/video0,format=rgb24") == "format");
  CHECK(input_error_field("v4l2:/dev/video0,row_time_us=0.03") == "row_time_us");  // ms given as us
  CHECK(input_error_field("v4l2:/dev/video0,row_time_us=30000") == "row_time_us");  // ns given as us
  CHECK(input_error_field("v4l2:/dev/video0,exposure=100") == "exposure");
  CHECK(input_error_field("v4l2:video0") == "--source");
  CHECK_THROWS_AS(SourceSpec::parse("v4l2:/dev/video0,width"), InputError);
  try {
    (void)v4l2_options_from_spec(SourceSpec::parse("v4l2:/dev/video0,format=rgb24"));
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("grey, yuyv or mjpeg"));
  }
}

TEST_CASE("exposure: microseconds <-> 100 us units, clamped to the control's range with a message", "[v4l2]") {
  const ControlRange c920{3, 2047, 1, 250};
  ExposureUnits e = exposure_us_to_units(300.0, c920);
  CHECK(e.units == 3);
  CHECK(e.applied_us == 300.0);
  CHECK_FALSE(e.adjusted);
  CHECK(e.message.empty());

  e = exposure_us_to_units(100.0, c920);  // below the C920's minimum of 3 units
  CHECK(e.units == 3);
  CHECK(e.applied_us == 300.0);
  CHECK(e.adjusted);
  CHECK_THAT(e.message, Catch::Contains("100 us") && Catch::Contains("below the camera's minimum") &&
                            Catch::Contains("300 us"));

  e = exposure_us_to_units(1e6, c920);
  CHECK(e.units == 2047);
  CHECK_THAT(e.message, Catch::Contains("above the camera's maximum"));

  e = exposure_us_to_units(250.0, {1, 5000, 1, 156});  // 2.5 units: rounds to a whole unit
  CHECK((e.units == 2 || e.units == 3));
  CHECK(e.adjusted);
  e = exposure_us_to_units(700.0, {2, 100, 4, 2});  // valid values 2, 6, 10, ...
  CHECK(e.units == 6);
  CHECK_THAT(e.message, Catch::Contains("step"));
  e = exposure_us_to_units(10000.0, {2, 100, 4, 2});  // 100 is off the grid: the last valid value
  CHECK(e.units == 98);
  CHECK(exposure_units_to_us(e.units) == 9800.0);
}

TEST_CASE("exposure control names: both kernels' spellings", "[v4l2]") {
  CHECK(v4l2_control_name("Exposure Time, Absolute") == "exposure_time_absolute");
  CHECK(v4l2_control_name("Exposure (Absolute)") == "exposure_absolute");
  CHECK(v4l2_control_name("White Balance Temperature, Auto") == "white_balance_temperature_auto");
  CHECK(is_exposure_absolute_name("Exposure Time, Absolute"));
  CHECK(is_exposure_absolute_name("Exposure (Absolute)"));
  CHECK(is_exposure_absolute_name("exposure_time_absolute"));
  CHECK(is_exposure_absolute_name("exposure_absolute"));
  CHECK_FALSE(is_exposure_absolute_name("Exposure, Auto"));
  CHECK(is_auto_exposure_name("Auto Exposure"));
  CHECK(is_auto_exposure_name("Exposure, Auto"));
  CHECK(is_exposure_dynamic_framerate_name("Exposure, Dynamic Framerate"));
  CHECK(is_exposure_dynamic_framerate_name("Exposure, Auto Priority"));
  CHECK_FALSE(is_exposure_dynamic_framerate_name("Gain"));
}

TEST_CASE("opening /dev/video99 and a non-V4L2 file give clear errors", "[v4l2]") {
  REQUIRE_FALSE(std::filesystem::exists("/dev/video99"));
  try {
    (void)make_live_source(SourceSpec::parse("v4l2:/dev/video99"));
    FAIL("no error");
  } catch (const V4l2Error& e) {
    CHECK(e.kind() == V4l2Error::Kind::no_device);
    CHECK_THAT(e.what(), Catch::Contains("/dev/video99") && Catch::Contains("no such device") &&
                             Catch::Contains("luxloc devices"));
  }
  try {
    V4l2CameraOptions o;
    o.path = "/dev/null";
    V4l2CameraSource s(o);
    FAIL("no error");
  } catch (const V4l2Error& e) {
    CHECK(e.kind() == V4l2Error::Kind::not_capture);
    CHECK_THAT(e.what(), Catch::Contains("/dev/null") && Catch::Contains("not a V4L2 device"));
  }
  // The CLI: a device that cannot be opened is a runtime failure (exit 1), a bad spec bad usage (2).
  const auto dir = test::scratch_dir("v4l2_cli");
  test::write_text(dir / "ledmap.yaml", "%YAML:1.0\n---\nleds:\n   - { id: 1, freq_hz: 2000., x: 1., y: 1., z: 3. }\n");
  test::write_text(dir / "camera.yaml",
                   "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n   rows: 3\n"
                   "   cols: 3\n   dt: d\n   data: [ 460., 0., 320., 0., 460., 240., 0., 0., 1. ]\n"
                   "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                   "   data: [ 0., 0., 0., 0., 0. ]\nrow_time_us: 30.\nexposure_us: 100.\n");
  const std::string common = " --map '" + (dir / "ledmap.yaml").string() + "' --camera '" + (dir / "camera.yaml").string() + "'";
  auto r = test::run_luxloc("vlc --source v4l2:/dev/video99" + common);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Catch::Contains("/dev/video99: no such device"));
  r = test::run_luxloc("vlc --source v4l2:/dev/video99,format=bgr" + common);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("format"));
}
