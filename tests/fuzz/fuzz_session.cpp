// libFuzzer target: a whole session, end to end (app/run_session: playback, pipeline,
// fusion, pose file). The input is a small session folder: its files joined by lines
// "=====" in this order: session.yaml, ledmap.yaml, camera.yaml, imu.csv, frames.csv,
// uwb.csv, fixes.csv (an empty part: the file is absent). frames/000000.png..000002.png
// are real 64x48 frames. The run ends in an InputError (exit 2) or writes poses, each with
// finite x and y (no silent NaN); no other exception, no crash, no hang.
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "app/run_session.hpp"
#include "core/common/input_error.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;
namespace fs = std::filesystem;

namespace {

const char* kFiles[] = {"session.yaml", "ledmap.yaml", "camera.yaml", "imu.csv", "frames.csv", "uwb.csv", "fixes.csv"};

void write_frames(const fs::path& dir) {
  fs::create_directories(dir);
  for (int i = 0; i < 3; ++i) {
    cv::Mat img(48, 64, CV_8UC1, cv::Scalar(10));
    for (int r = 0; r < img.rows; ++r)
      if ((r / (2 + i)) % 2 == 0) img.row(r).colRange(20, 44).setTo(230);  // a striped LED blob
    cv::imwrite((dir / ("00000" + std::to_string(i) + ".png")).string(), img);
  }
}

void check_poses(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const std::size_t c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1);
    if (c3 == std::string::npos || c2 == c1 + 1 || c3 == c2 + 1) fuzz::fail("pose without a finite x/y: " + line);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet_tbb = [] {
    write_frames(fuzz::scratch() / "frames");
    return true;
  }();
  (void)quiet_tbb;
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const auto parts = fuzz::split_parts(in, "=====", std::size(kFiles));
  const fs::path dir = fuzz::scratch() / "session";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::create_directory_symlink(fuzz::scratch() / "frames", dir / "frames");
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (!parts[i].empty()) fuzz::write_file(dir / kFiles[i], parts[i]);

  app::RunConfig cfg;
  cfg.playback = dir.string();
  cfg.out = (fuzz::scratch() / "poses.csv").string();
  cfg.quiet = true;
  cfg.status = "off";
  cfg.fusion.pf.particles = 200;    // the parsers and the state machine matter here, not accuracy
  std::ostringstream log;
  try {
    (void)app::run_session(cfg, log);
    check_poses(cfg.out);
  } catch (const InputError&) {
  }
  return 0;
}
