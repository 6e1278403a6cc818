// libFuzzer target: every YAML reader (LED map, camera, session.yaml, IMU calibration;
// core/common/yaml_reader). The input's first line names the reader, the rest is the file.
// A structural error must be an InputError naming the file (exit 2), never an OpenCV
// assertion (cv::Exception) or another exception; what loads is finite where it is used.
#include "core/common/input_error.hpp"
#include "core/common/session_file.hpp"
#include "core/imu/imu_calibration.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = in.find('\n');
  if (eol == std::string_view::npos) return 0;
  const std::string_view kind = in.substr(0, eol);
  const std::string path = (fuzz::scratch() / "input.yaml").string();
  fuzz::write_file(path, in.substr(eol + 1));
  try {
    if (kind == "ledmap") {
      const LedMap map = LedMap::load(path);
      for (const auto& led : map.leds()) {
        fuzz::expect_finite(led.freq_hz, "LED frequency");
        for (int k = 0; k < 3; ++k) fuzz::expect_finite(led.p_inW[k], "LED position");
      }
      (void)load_anchors(path);
    } else if (kind == "camera") {
      const CameraModel cam = CameraModel::load(path);
      if (cam.width <= 0 || cam.height <= 0) fuzz::fail("camera loaded with a size <= 0");
    } else if (kind == "session") {
      (void)load_session_config(path);
    } else if (kind == "imucalib") {
      (void)load_imu_calibration(path);
    }
  } catch (const InputError& e) {
    if (e.file() != path) fuzz::fail(std::string("InputError does not name the file: ") + e.what());
  }
  return 0;
}
