#pragma once
// Accelerometer bias and scale from static orientations (SEEDS.md C.4, "six-position"
// calibration). At rest the true specific force has magnitude g, so for the mean reading m_i
// of each static orientation |(m_i - b) / s| = g. The six-position closed form (each axis
// once up, once down: b = (m+ + m-) / 2, s = (m+ - m-) / 2g) starts a Gauss-Newton fit of
// the six unknowns to all orientations, which also uses tilted, imperfect positions.
#include <Eigen/Core>
#include <vector>

namespace luxloc {

struct AccelCalibrationResult {
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();   // m/s^2
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  double residual_rms_mps2 = 0.0;  // rms of |(m - b) / s| - g over the orientations
  int iterations = 0;
};

// `means`: mean static accelerometer readings (m/s^2), one per orientation. Throws
// std::invalid_argument when fewer than 6 are given or they do not span both directions of
// every axis (the fit would be ill-conditioned), naming the axes that are missing.
AccelCalibrationResult solve_accel_calibration(const std::vector<Eigen::Vector3d>& means, double gravity);

// "+z", "-x"...: the body axis closest to world up for a static reading.
const char* up_axis_name(const Eigen::Vector3d& acc_mean);

}  // namespace luxloc
