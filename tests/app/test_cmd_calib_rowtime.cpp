// `luxloc calib rowtime` as a user runs it: a folder with the real full-frame stripe photo,
// the camera file updated with --out, and the refusals (exit 2, saying why).
#include <catch2/catch.hpp>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/vlc/camera_model.hpp"
#include "test_support.hpp"

using namespace luxloc;

TEST_CASE("luxloc calib rowtime: the real 1000 Hz photo gives 14.57 us and updates camera.yaml", "[calib][vlc]") {
  const auto dir = test::scratch_dir("cmd_calib_rowtime");
  const auto images = dir / "frames";
  std::filesystem::create_directories(images);
  std::filesystem::copy_file(test::shared_dir() / "realdata/rolling_shutter_readout/frame_example.png",
                             images / "frame_example.png", std::filesystem::copy_options::overwrite_existing);
  CameraModel base;
  base.width = 1920;
  base.height = 1080;
  base.fx = base.fy = 1500;
  base.cx = 960;
  base.cy = 540;
  base.row_time_s = 30e-6;  // the placeholder `calib camera` writes
  base.save((dir / "camera.yaml").string());

  auto r = test::run_luxloc("calib rowtime --freq 1000 --images '" + images.string() + "' --camera '" +
                            (dir / "camera.yaml").string() + "' --out '" + (dir / "measured.yaml").string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("1 of 1 frames used: row time 14.5") != std::string::npos);
  CHECK(r.output.find("-51.") != std::string::npos);  // against the 30 us placeholder
  const CameraModel measured = CameraModel::load((dir / "measured.yaml").string());
  CHECK(measured.row_time_s * 1e6 == Approx(15.730e3 / 1080.0).epsilon(0.003));
  CHECK(measured.fx == base.fx);  // everything else kept
  CHECK(measured.width == base.width);

  // The wrong frequency (no LED stripes fit the range) and a dark folder: exit 2, saying why.
  r = test::run_luxloc("calib rowtime --freq 1000 --images '" + images.string() + "' --max-us 5");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("no frame showed enough stripes") != std::string::npos);
  const auto dark = dir / "dark";
  std::filesystem::create_directories(dark);
  cv::imwrite((dark / "black.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(3)));
  r = test::run_luxloc("calib rowtime --freq 1000 --images '" + dark.string() + "'");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("refused: no light above the background") != std::string::npos);
  // --out needs the camera file it updates.
  r = test::run_luxloc("calib rowtime --freq 1000 --images '" + images.string() + "' --out '" +
                       (dir / "x.yaml").string() + "'");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--out needs --camera") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "x.yaml"));
}
