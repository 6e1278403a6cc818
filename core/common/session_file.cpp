#include "core/common/session_file.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <set>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

// An empty file (or one holding only the YAML preamble) is a valid, all-defaults session.
bool blank_yaml(const std::string& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec) && std::filesystem::file_size(path, ec) == 0;
}

cv::FileStorage open_yaml(const std::string& path, const char* what) {
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML))
      throw InputError(path, 0, "", std::string("cannot open ") + what);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", std::string("not a valid OpenCV YAML file: ") + e.err);
  }
  return fs;
}

double anchor_number(const std::string& path, std::size_t index, const cv::FileNode& a, const char* key) {
  const cv::FileNode n = a[key];
  const std::string label = "anchor #" + std::to_string(index + 1);
  if (n.empty()) throw InputError(path, 0, std::string("anchors.") + key, label + ": missing required field");
  if (!n.isReal() && !n.isInt()) throw InputError(path, 0, std::string("anchors.") + key, label + ": not a number");
  const double v = static_cast<double>(n);
  if (!std::isfinite(v)) throw InputError(path, 0, std::string("anchors.") + key, label + ": not finite");
  return v;
}

std::vector<UwbAnchor> read_anchors(const cv::FileStorage& fs, const std::string& path) {
  std::vector<UwbAnchor> anchors;
  const cv::FileNode seq = fs["anchors"];
  if (seq.empty() || seq.isNone()) return anchors;
  if (!seq.isSeq()) throw InputError(path, 0, "anchors", "not a sequence of {id, x, y, z}");
  std::set<int> ids;
  std::size_t index = 0;
  for (auto it = seq.begin(); it != seq.end(); ++it, ++index) {
    const cv::FileNode a = *it;
    const std::string label = "anchor #" + std::to_string(index + 1);
    if (!a.isMap()) throw InputError(path, 0, "anchors", label + ": not a mapping {id, x, y, z}");
    const cv::FileNode idn = a["id"];
    if (idn.empty()) throw InputError(path, 0, "anchors.id", label + ": missing required field");
    if (!idn.isInt()) throw InputError(path, 0, "anchors.id", label + ": not an integer");
    UwbAnchor u;
    u.id = static_cast<int>(idn);
    if (!ids.insert(u.id).second)
      throw InputError(path, 0, "anchors.id", label + ": duplicate id " + std::to_string(u.id));
    u.p_inW = {anchor_number(path, index, a, "x"), anchor_number(path, index, a, "y"),
               anchor_number(path, index, a, "z")};
    anchors.push_back(u);
  }
  return anchors;
}

void read_file_name(const cv::FileStorage& fs, const std::string& path, const char* key, std::string& out) {
  const cv::FileNode n = fs[key];
  if (n.empty() || n.isNone()) return;
  if (!n.isString()) throw InputError(path, 0, key, "not a file name (string)");
  const std::string s = static_cast<std::string>(n);
  if (s.empty()) throw InputError(path, 0, key, "empty file name");
  out = s;
}

}  // namespace

std::vector<UwbAnchor> load_anchors(const std::string& path) {
  if (blank_yaml(path)) return {};
  const cv::FileStorage fs = open_yaml(path, "YAML file");
  return read_anchors(fs, path);
}

SessionConfig load_session_config(const std::string& path) {
  SessionConfig c;
  if (blank_yaml(path)) return c;
  const cv::FileStorage fs = open_yaml(path, "session file");
  const cv::FileNode h = fs["device_height_m"];
  if (!h.empty() && !h.isNone()) {
    if (!h.isReal() && !h.isInt()) throw InputError(path, 0, "device_height_m", "not a number");
    c.device_height_m = static_cast<double>(h);
    if (!std::isfinite(c.device_height_m) || c.device_height_m < 0.0)
      throw InputError(path, 0, "device_height_m", "must be a finite height >= 0 (m)");
  }
  c.anchors = read_anchors(fs, path);
  read_file_name(fs, path, "imu", c.imu_file);
  read_file_name(fs, path, "frames", c.frames_file);
  read_file_name(fs, path, "uwb", c.uwb_file);
  read_file_name(fs, path, "fixes", c.fixes_file);
  read_file_name(fs, path, "odom", c.odom_file);
  read_file_name(fs, path, "groundtruth", c.groundtruth_file);
  read_file_name(fs, path, "ledmap", c.ledmap_file);
  read_file_name(fs, path, "camera", c.camera_file);
  return c;
}

void save_session_config(const SessionConfig& c, const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", std::string("cannot write session file: ") + e.err);
  }
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot write session file");
  if (std::isfinite(c.device_height_m)) fs << "device_height_m" << c.device_height_m;
  if (!c.anchors.empty()) {
    fs << "anchors" << "[";
    for (const UwbAnchor& a : c.anchors)
      fs << "{:" << "id" << a.id << "x" << a.p_inW.x() << "y" << a.p_inW.y() << "z" << a.p_inW.z() << "}";
    fs << "]";
  }
  fs << "imu" << c.imu_file << "frames" << c.frames_file << "uwb" << c.uwb_file << "fixes" << c.fixes_file
     << "odom" << c.odom_file << "groundtruth" << c.groundtruth_file << "ledmap" << c.ledmap_file
     << "camera" << c.camera_file;
}

}  // namespace luxloc
