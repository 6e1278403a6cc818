#include "core/imu/imu_calibration.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>
#include <stdexcept>

#include "core/common/input_error.hpp"
#include "core/common/yaml_reader.hpp"

namespace luxloc {
namespace {

constexpr double kMinScale = 0.5, kMaxScale = 2.0;

// Reads a 3-element numeric sequence (or a 3-element opencv-matrix) into `out`; returns
// false when the key is absent.
bool read_vec3(const YamlFile& f, const char* key, Eigen::Vector3d& out) {
  const cv::FileNode n = f[key];
  if (n.empty()) return false;
  Eigen::Vector3d v;
  if (n.isSeq()) {
    if (n.size() != 3) f.fail(key, "", "expected 3 numbers, got " + std::to_string(n.size()));
    for (int i = 0; i < 3; ++i) v[i] = f.number(n[i], key, "element " + std::to_string(i));
  } else if (n.isMap()) {
    const cv::Mat m = f.matrix(n, key);
    if (m.total() != 3) f.fail(key, "", "expected 3 numbers");
    for (int i = 0; i < 3; ++i) v[i] = m.at<double>(i);
  } else {
    f.fail(key, "", "expected a sequence of 3 numbers");
  }
  out = v;
  return true;
}

void check_scale(const std::string& path, const char* key, const Eigen::Vector3d& s) {
  if (s.minCoeff() < kMinScale || s.maxCoeff() > kMaxScale)
    throw InputError(path, 0, key, "scale factors must lie in [0.5, 2]");
}

void write_vec3(cv::FileStorage& fs, const char* key, const Eigen::Vector3d& v) {
  fs << key << "[:" << v.x() << v.y() << v.z() << "]";
}

}  // namespace

ImuSample ImuCalibration::apply(const ImuSample& m) const {
  ImuSample s = m;
  s.gyro_inB = (m.gyro_inB - gyro_bias).cwiseQuotient(gyro_scale);
  s.acc_inB = (m.acc_inB - acc_bias).cwiseQuotient(acc_scale);
  if (m.has_mag) s.mag_inB = (m.mag_inB - mag_bias).cwiseQuotient(mag_scale);
  return s;
}

bool ImuCalibration::is_identity() const {
  return gyro_bias.isZero(0) && acc_bias.isZero(0) && mag_bias.isZero(0) && gyro_scale.isOnes(0) &&
         acc_scale.isOnes(0) && mag_scale.isOnes(0);
}

ImuCalibration load_imu_calibration(const std::string& path) {
  const YamlFile f(path, "IMU calibration file");
  ImuCalibration c;
  int found = 0;
  found += read_vec3(f, "gyro_bias", c.gyro_bias);
  found += read_vec3(f, "gyro_scale", c.gyro_scale);
  found += read_vec3(f, "acc_bias", c.acc_bias);
  found += read_vec3(f, "acc_scale", c.acc_scale);
  found += read_vec3(f, "mag_bias", c.mag_bias);
  found += read_vec3(f, "mag_scale", c.mag_scale);
  if (found == 0)
    throw InputError(path, 0, "", "no calibration keys (gyro_bias, gyro_scale, acc_bias, acc_scale, mag_bias, mag_scale)");
  check_scale(path, "gyro_scale", c.gyro_scale);
  check_scale(path, "acc_scale", c.acc_scale);
  check_scale(path, "mag_scale", c.mag_scale);
  return c;
}

void save_imu_calibration(const std::string& path, const ImuCalibration& c, const ImuCalibrationInfo& info) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!fs.isOpened()) throw std::runtime_error("cannot write IMU calibration file '" + path + "'");
  fs.writeComment("luxloc IMU calibration: measured = scale * true + bias, per body axis (FLU)");
  fs.writeComment("gyro rad/s, acc m/s^2, mag microtesla");
  write_vec3(fs, "gyro_bias", c.gyro_bias);
  write_vec3(fs, "gyro_scale", c.gyro_scale);
  write_vec3(fs, "acc_bias", c.acc_bias);
  write_vec3(fs, "acc_scale", c.acc_scale);
  write_vec3(fs, "mag_bias", c.mag_bias);
  write_vec3(fs, "mag_scale", c.mag_scale);
  if (!info.method.empty()) fs << "method" << info.method;
  if (info.acc_residual_rms_mps2 >= 0.0) fs << "acc_residual_rms_mps2" << info.acc_residual_rms_mps2;
  if (info.static_segments > 0) {
    fs << "static_segments" << info.static_segments;
    fs << "static_seconds" << info.static_seconds;
  }
}

}  // namespace luxloc
