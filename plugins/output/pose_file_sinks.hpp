#pragma once
// Pose files (SPEC.md "Pose output"), `--out FILE` ("-" = stdout) with `--format csv|tum`.
//
// CSV: a header row, then one row per pose, columns in this order:
//   t,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode,sigma_yaw,sigma_z
// t in seconds with 6 decimals (printed from the integer ns timeline), positions and
// sigmas in m with 5 decimals, angles in rad with 5 decimals, n_eff with 1 decimal.
// An unknown value (NaN: sigma before the filter has one, n_eff of a non-particle filter)
// is written as an EMPTY field, never "nan"; `mode` has commas/newlines replaced by '_'.
//
// TUM: `t tx ty tz qx qy qz qw`, space separated, no header; the quaternion is the body's
// attitude in the world (R_BtoW = Rz(yaw) Ry(pitch) Rx(roll), ZYX), with qw >= 0. A pose
// whose position or yaw is not finite cannot be written in TUM and is dropped and counted
// ("not finite"); NaN roll/pitch count as 0 (level).
#include <Eigen/Geometry>
#include <string>

#include "core/pipeline/pose_sink.hpp"
#include "plugins/output/text_file.hpp"

namespace luxloc {

enum class PoseFileFormat { kCsv, kTum };

// "csv" or "tum"; anything else -> InputError naming the option.
PoseFileFormat parse_pose_format(const std::string& name);

inline constexpr const char* kPoseCsvHeader = "t,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode,sigma_yaw,sigma_z,motion";
// One CSV data row (with its '\n').
std::string pose_csv_row(const PoseEstimate& pose);
// One TUM line (with its '\n'); empty when the pose is not finite.
std::string pose_tum_line(const PoseEstimate& pose);
// R_BtoW = Rz(yaw) Ry(pitch) Rx(roll) as a unit quaternion with w >= 0.
Eigen::Quaterniond quaternion_from_ypr(double yaw, double pitch, double roll);

class CsvPoseSink : public PoseSink {
 public:
  // Creates the file and writes the header (InputError when it cannot be created).
  explicit CsvPoseSink(const std::string& out);
  std::string name() const override { return "csv:" + file_.path(); }
  void write(const PoseEstimate& pose) override { file_.write(pose_csv_row(pose)); }
  void flush() override { file_.flush(); }

 private:
  TextFile file_;
};

class TumPoseSink : public PoseSink {
 public:
  explicit TumPoseSink(const std::string& out) : file_(out) {}
  std::string name() const override { return "tum:" + file_.path(); }
  void write(const PoseEstimate& pose) override;
  void flush() override { file_.flush(); }

 private:
  TextFile file_;
};

PoseSinkPtr make_pose_file_sink(const std::string& out, PoseFileFormat format);

}  // namespace luxloc
