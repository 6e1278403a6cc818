#include "plugins/output/pose_file_sinks.hpp"

#include <cmath>

#include "core/common/input_error.hpp"
#include "plugins/output/pose_text.hpp"

namespace luxloc {
namespace {

double or_zero(double v) { return std::isfinite(v) ? v : 0.0; }

}  // namespace

PoseFileFormat parse_pose_format(const std::string& name) {
  if (name == "csv") return PoseFileFormat::kCsv;
  if (name == "tum") return PoseFileFormat::kTum;
  throw InputError("--format", 0, "", "unknown pose format '" + name + "' (expected csv or tum)");
}

std::string pose_csv_row(const PoseEstimate& p) {
  std::string mode = p.mode;
  std::string motion = p.motion;
  for (std::string* text : {&mode, &motion})
    for (char& ch : *text)
      if (ch == ',' || ch == '\n' || ch == '\r') ch = '_';
  std::string s;
  s.reserve(128);
  s += format_time_s(p.t, 6);
  for (double v : {p.p_BinW.x(), p.p_BinW.y(), p.p_BinW.z(), p.yaw, p.sigma_x, p.sigma_y, p.roll, p.pitch}) {
    s += ',';
    s += format_fixed(v, 5);
  }
  s += ',';
  s += format_fixed(p.n_eff, 1);
  s += ',';
  s += std::to_string(p.leds);
  s += ',';
  s += mode;
  s += ',';
  s += format_fixed(p.sigma_yaw, 5);
  s += ',';
  s += format_fixed(p.sigma_z, 5);
  s += ',';
  s += motion;
  s += '\n';
  return s;
}

Eigen::Quaterniond quaternion_from_ypr(double yaw, double pitch, double roll) {
  Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return q;
}

std::string pose_tum_line(const PoseEstimate& p) {
  if (!p.p_BinW.allFinite()) return {};
  // An unknown attitude (no IMU) is written as the identity: TUM has no "unknown", and the
  // trajectory tools evaluate the position alone well.
  const Eigen::Quaterniond q = quaternion_from_ypr(or_zero(p.yaw), or_zero(p.pitch), or_zero(p.roll));
  std::string s = format_time_s(p.t, 6);
  for (double v : {p.p_BinW.x(), p.p_BinW.y(), p.p_BinW.z()}) {
    s += ' ';
    s += format_fixed(v, 5);
  }
  for (double v : {q.x(), q.y(), q.z(), q.w()}) {
    s += ' ';
    s += format_fixed(v, 7);
  }
  s += '\n';
  return s;
}

CsvPoseSink::CsvPoseSink(const std::string& out) : file_(out) {
  file_.write(kPoseCsvHeader);
  file_.write("\n");
}

void TumPoseSink::write(const PoseEstimate& pose) {
  const std::string line = pose_tum_line(pose);
  if (line.empty()) {
    drops().add("not finite", "pose at t = " + format_time_s(pose.t) + " s has a non-finite position");
    return;
  }
  file_.write(line);
}

PoseSinkPtr make_pose_file_sink(const std::string& out, PoseFileFormat format) {
  if (format == PoseFileFormat::kTum) return std::make_unique<TumPoseSink>(out);
  return std::make_unique<CsvPoseSink>(out);
}

}  // namespace luxloc
