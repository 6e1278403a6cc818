#include "plugins/playback/playback_session.hpp"

#include "core/common/input_error.hpp"
#include "plugins/playback/fix_csv_source.hpp"
#include "plugins/playback/frame_list_source.hpp"
#include "plugins/playback/imu_csv_source.hpp"
#include "plugins/playback/odom_csv_source.hpp"
#include "core/common/session_file.hpp"
#include "plugins/playback/uwb_csv_source.hpp"

namespace luxloc {
namespace {

namespace fs = std::filesystem;

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// The session file for `name` if it exists. A name that differs from SPEC's default came
// from session.yaml, so its absence is an error rather than "sensor not recorded".
std::optional<fs::path> session_file(const fs::path& dir, const std::string& name, const std::string& fallback,
                                     const char* key) {
  const fs::path p = dir / name;
  if (is_file(p)) return p;
  if (name != fallback)
    throw InputError((dir / "session.yaml").string(), 0, key, "names '" + name + "', which does not exist");
  return std::nullopt;
}

fs::path explicit_file(const fs::path& p, const char* option) {
  if (!is_file(p)) throw InputError(p.string(), 0, "", std::string(option) + ": file not found");
  return p;
}

}  // namespace

PlaybackSession open_playback(const fs::path& dir, const PlaybackOptions& options) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw InputError(dir.string(), 0, "", "session folder not found");
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string(), 0, "", "not a folder (expected a session folder)");

  PlaybackSession s;
  s.dir = dir;
  if (const fs::path yaml = dir / "session.yaml"; is_file(yaml)) s.config = load_session_config(yaml.string());
  const SessionConfig defaults;
  const SessionConfig& c = s.config;

  std::optional<fs::path> map_file = options.map_path.empty()
                                         ? session_file(dir, c.ledmap_file, defaults.ledmap_file, "ledmap")
                                         : explicit_file(options.map_path, "--map");
  if (map_file) {
    s.map = LedMap::load(map_file->string(), options.map_options);
    if (s.config.anchors.empty()) s.config.anchors = load_anchors(map_file->string());
  }
  const std::optional<fs::path> camera_file = options.camera_path.empty()
                                                  ? session_file(dir, c.camera_file, defaults.camera_file, "camera")
                                                  : explicit_file(options.camera_path, "--camera");
  if (camera_file) s.camera = CameraModel::load(camera_file->string());
  s.groundtruth = session_file(dir, c.groundtruth_file, defaults.groundtruth_file, "groundtruth");

  if (auto p = session_file(dir, c.imu_file, defaults.imu_file, "imu"))
    s.sources.push_back(std::make_unique<ImuCsvSource>(p->string()));
  if (auto p = session_file(dir, c.frames_file, defaults.frames_file, "frames")) {
    std::optional<cv::Size> size;
    if (s.camera && options.check_frame_size) size = cv::Size(s.camera->width, s.camera->height);
    s.sources.push_back(std::make_unique<FrameListSource>(p->string(), dir, size));
  }
  if (auto p = session_file(dir, c.uwb_file, defaults.uwb_file, "uwb"))
    s.sources.push_back(std::make_unique<UwbCsvSource>(p->string()));
  if (auto p = session_file(dir, c.fixes_file, defaults.fixes_file, "fixes"))
    s.sources.push_back(std::make_unique<FixCsvSource>(p->string()));
  if (auto p = session_file(dir, c.odom_file, defaults.odom_file, "odom"))
    s.sources.push_back(std::make_unique<OdomCsvSource>(p->string()));

  for (SourcePtr& src : s.sources) static_cast<CsvRowSource&>(*src).set_limits(c.limits);

  if (s.sources.empty())
    throw InputError(dir.string(), 0, "",
                     "no sensor file in the session folder (expected at least one of " + c.imu_file + ", " +
                         c.frames_file + ", " + c.uwb_file + ", " + c.fixes_file + ", " + c.odom_file + ")");
  return s;
}

}  // namespace luxloc
