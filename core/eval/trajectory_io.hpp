#pragma once
// Trajectories for evaluation: ground truth (SPEC.md groundtruth.csv: t,x,y[,z,yaw]) and
// estimated poses (the CSV pose output, columns found by name, or a TUM file).
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "core/common/pose.hpp"
#include "core/common/time.hpp"

namespace luxloc {

struct TrajectoryPoint {
  TimeNs t = 0;
  Eigen::Vector3d p_inW = Eigen::Vector3d::Zero();  // z = 0 when the file has none
  double yaw = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  // The estimate's own 1-sigma (pose files' sigma_x, sigma_y, sigma_yaw; NaN: not given),
  // for the consistency figures of `luxloc eval`.
  double sigma_x = std::numeric_limits<double>::quiet_NaN();
  double sigma_y = std::numeric_limits<double>::quiet_NaN();
  double sigma_yaw = std::numeric_limits<double>::quiet_NaN();
  double sigma_z = std::numeric_limits<double>::quiet_NaN();  // NaN: z not estimated
};
using TruthRow = TrajectoryPoint;
using PoseRow = TrajectoryPoint;

inline PoseRow to_pose_row(const PoseEstimate& p) { return {p.t, p.p_BinW, p.yaw, p.sigma_x, p.sigma_y, p.sigma_yaw, p.sigma_z}; }

// groundtruth.csv: t,x,y required; z, yaw optional (empty yaw field -> NaN). Evaluation is
// strict: any bad row, fewer than 2 rows, or times not strictly increasing -> InputError
// (file, line, field).
std::vector<TruthRow> read_truth_csv(const std::string& path);

// A pose file: CSV with a header (t,x,y required; z, yaw optional; found by name) or,
// when the first non-comment line starts with a number, TUM (`t tx ty tz qx qy qz qw`,
// whitespace separated, '#' comments; yaw taken from the quaternion). Any bad row ->
// InputError; a file without a pose -> InputError "no poses". Rows need not be sorted.
std::vector<PoseRow> read_pose_file(const std::string& path);

}  // namespace luxloc
