// libFuzzer target: the session CSV readers (plugins/playback, core/eval/trajectory_io).
// The input's first line names the file (imu, frames, uwb, fixes, odom, groundtruth, poses),
// the rest is its content. Playback must end in an InputError (a missing column) or stream
// to the end, skipping and counting bad rows; every sample that comes out is plausible
// (core/common/sensor_limits) and in time order. The evaluation readers are strict: a
// trajectory or an InputError.
#include <algorithm>

#include "core/common/input_error.hpp"
#include "core/common/sensor_limits.hpp"
#include "core/eval/trajectory_io.hpp"
#include "plugins/playback/playback_session.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;
namespace fs = std::filesystem;

namespace {

void play(const fs::path& dir) {
  PlaybackSession session = open_playback(dir);
  const SensorLimits limits;
  for (SourcePtr& source : session.sources) {
    SensorData d;
    TimeNs last = std::numeric_limits<TimeNs>::min();
    for (int n = 0; n < 100'000 && source->next(d); ++n) {
      if (auto bad = check_plausible(d, limits)) fuzz::fail("implausible sample passed: " + bad->field + ": " + bad->what);
      // Strictly increasing, except UWB: ranges to several anchors may share a time stamp.
      const bool same_ok = std::holds_alternative<UwbSample>(d);
      if (sample_time(d) < last || (sample_time(d) == last && !same_ok)) fuzz::fail("samples out of time order");
      last = sample_time(d);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = in.find('\n');
  if (eol == std::string_view::npos) return 0;
  const std::string kind(in.substr(0, eol));
  const std::string_view body = in.substr(eol + 1);
  static const std::vector<std::string> kKinds = {"imu", "frames", "uwb", "fixes", "odom", "groundtruth", "poses"};
  if (std::find(kKinds.begin(), kKinds.end(), kind) == kKinds.end()) return 0;

  const fs::path dir = fuzz::scratch() / "session";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  const fs::path file = dir / (kind + ".csv");
  fuzz::write_file(file, body);
  // frames.csv points at images: give it one real (tiny) image and one that is not an image.
  fuzz::write_file(dir / "frames" / "bad.png", "\x89PNG\r\n\x1a\n truncated");
  try {
    if (kind == "groundtruth")
      (void)read_truth_csv(file.string());
    else if (kind == "poses")
      (void)read_pose_file(file.string());
    else
      play(dir);
  } catch (const InputError&) {
    // exit 2 with file/line/field: the promised outcome for a file that cannot be read
  }
  return 0;
}
