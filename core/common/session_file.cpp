#include "core/common/session_file.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <set>

#include "core/common/input_error.hpp"
#include "core/common/yaml_reader.hpp"

namespace luxloc {
namespace {

double anchor_number(const YamlFile& f, const cv::FileNode& a, const std::string& label, const char* key) {
  const std::string field = std::string("anchors.") + key;
  const cv::FileNode n = f.member(a, key, label);
  if (n.empty()) f.fail(field, label, "missing required field");
  return f.number(n, field, label);
}

std::vector<UwbAnchor> read_anchors(const YamlFile& f) {
  std::vector<UwbAnchor> anchors;
  const cv::FileNode seq = f["anchors"];
  if (seq.empty()) return anchors;
  if (!seq.isSeq()) f.fail("anchors", "", "not a sequence of {id, x, y, z}");
  std::set<int> ids;
  std::size_t index = 0;
  for (auto it = seq.begin(); it != seq.end(); ++it, ++index) {
    const cv::FileNode a = *it;
    const std::string label = "anchor #" + std::to_string(index + 1);
    if (!a.isMap()) f.fail("anchors", label, "not a mapping {id, x, y, z}");
    const cv::FileNode idn = f.member(a, "id", label);
    if (idn.empty()) f.fail("anchors.id", label, "missing required field");
    UwbAnchor u;
    u.id = f.integer(idn, "anchors.id", label);
    if (!ids.insert(u.id).second) f.fail("anchors.id", label, "duplicate id " + std::to_string(u.id));
    u.p_inW = {anchor_number(f, a, label, "x"), anchor_number(f, a, label, "y"), anchor_number(f, a, label, "z")};
    if (const cv::FileNode b = f.member(a, "bias_m", label); !b.empty()) u.bias_m = f.number(b, "anchors.bias_m", label);
    if (const cv::FileNode k = f.member(a, "scale", label); !k.empty()) {
      u.scale = f.number(k, "anchors.scale", label);
      if (!(u.scale > 0.5 && u.scale < 2.0)) f.fail("anchors.scale", label, "not in (0.5, 2)");
    }
    anchors.push_back(u);
  }
  return anchors;
}

void read_file_name(const YamlFile& f, const char* key, std::string& out) {
  const cv::FileNode n = f[key];
  if (n.empty()) return;
  if (!n.isString()) f.fail(key, "", "not a file name (string)");
  const std::string s = static_cast<std::string>(n);
  if (s.empty()) f.fail(key, "", "empty file name");
  out = s;
}

// `sensor_limits: {acc_max_g, gyro_max_dps, mag_max_ut, range_max_m}`: the sensors' ranges
// when they differ from the defaults (core/common/sensor_limits.hpp).
void read_sensor_limits(const YamlFile& f, SensorLimits& l) {
  const cv::FileNode m = f["sensor_limits"];
  if (m.empty()) return;
  f.expect_map(m, "sensor_limits", "");
  const auto positive = [&](const char* key, double scale, double& out) {
    const cv::FileNode n = f.member(m, key, "sensor_limits");
    if (n.empty()) return;
    const std::string field = std::string("sensor_limits.") + key;
    const double v = f.number(n, field, "");
    if (!(v > 0.0)) f.fail(field, "", "must be > 0");
    out = v * scale;
  };
  positive("acc_max_g", SensorLimits::kStandardGravity, l.acc_max_mps2);
  positive("gyro_max_dps", 3.141592653589793 / 180.0, l.gyro_max_rad_s);
  positive("mag_max_ut", 1.0, l.mag_max_ut);
  positive("range_max_m", 1.0, l.range_max_m);
}

}  // namespace

std::vector<UwbAnchor> load_anchors(const std::string& path) { return read_anchors(YamlFile(path, "YAML file")); }

SessionConfig load_session_config(const std::string& path) {
  SessionConfig c;
  const YamlFile f(path, "session file");
  const cv::FileNode h = f["device_height_m"];
  if (!h.empty()) {
    c.device_height_m = f.number(h, "device_height_m", "");
    if (c.device_height_m < 0.0) f.fail("device_height_m", "", "must be a finite height >= 0 (m)");
  }
  c.anchors = read_anchors(f);
  if (const cv::FileNode n = f["start"]; !n.empty()) {
    if (!n.isMap()) f.fail("start", "", "must be a map {x: .., y: .., yaw: .., sigma_m: ..}");
    StartPose s;
    s.p_inW = {f.number(n["x"], "start.x", ""), f.number(n["y"], "start.y", "")};
    if (!n["yaw"].empty()) s.yaw = f.number(n["yaw"], "start.yaw", "");
    if (!n["sigma_m"].empty()) {
      s.sigma_m = f.number(n["sigma_m"], "start.sigma_m", "");
      if (!(s.sigma_m > 0.0)) f.fail("start.sigma_m", "", "must be > 0 (m)");
    }
    c.start = s;
  }
  read_sensor_limits(f, c.limits);
  read_file_name(f, "imu", c.imu_file);
  read_file_name(f, "frames", c.frames_file);
  read_file_name(f, "uwb", c.uwb_file);
  read_file_name(f, "fixes", c.fixes_file);
  read_file_name(f, "odom", c.odom_file);
  read_file_name(f, "groundtruth", c.groundtruth_file);
  read_file_name(f, "ledmap", c.ledmap_file);
  read_file_name(f, "camera", c.camera_file);
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
  if (c.start) {
    fs << "start" << "{" << "x" << c.start->p_inW.x() << "y" << c.start->p_inW.y();
    if (std::isfinite(c.start->yaw)) fs << "yaw" << c.start->yaw;
    fs << "sigma_m" << c.start->sigma_m << "}";
  }
  if (!c.anchors.empty()) {
    fs << "anchors" << "[";
    for (const UwbAnchor& a : c.anchors)
    {
      fs << "{:" << "id" << a.id << "x" << a.p_inW.x() << "y" << a.p_inW.y() << "z" << a.p_inW.z();
      if (a.bias_m != 0.0 || a.scale != 1.0) fs << "bias_m" << a.bias_m << "scale" << a.scale;  // calibrated only
      fs << "}";
    }
    fs << "]";
  }
  fs << "imu" << c.imu_file << "frames" << c.frames_file << "uwb" << c.uwb_file << "fixes" << c.fixes_file
     << "odom" << c.odom_file << "groundtruth" << c.groundtruth_file << "ledmap" << c.ledmap_file
     << "camera" << c.camera_file;
}

}  // namespace luxloc
