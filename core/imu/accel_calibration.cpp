#include "core/imu/accel_calibration.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

namespace luxloc {

const char* up_axis_name(const Eigen::Vector3d& a) {
  static const char* names[3][2] = {{"+x", "-x"}, {"+y", "-y"}, {"+z", "-z"}};
  Eigen::Index i = 0;
  a.cwiseAbs().maxCoeff(&i);
  return names[i][a[i] >= 0.0 ? 0 : 1];
}

AccelCalibrationResult solve_accel_calibration(const std::vector<Eigen::Vector3d>& means, double gravity) {
  if (means.size() < 6)
    throw std::invalid_argument("six-position calibration needs 6 static orientations, got " +
                                std::to_string(means.size()));
  // Closed form from the extreme readings of each axis; also checks the coverage: each
  // axis must have been near +g and near -g (cos 45 deg) at least once.
  AccelCalibrationResult r;
  std::string missing;
  for (int j = 0; j < 3; ++j) {
    double hi = -1e300, lo = 1e300;
    for (const Eigen::Vector3d& m : means) {
      hi = std::max(hi, m[j]);
      lo = std::min(lo, m[j]);
    }
    const char axis = static_cast<char>('x' + j);
    if (hi < 0.7 * gravity) missing += std::string(missing.empty() ? "" : ", ") + "+" + axis;
    if (lo > -0.7 * gravity) missing += std::string(missing.empty() ? "" : ", ") + "-" + axis;
    r.bias[j] = 0.5 * (hi + lo);
    r.scale[j] = (hi - lo) / (2.0 * gravity);
  }
  if (!missing.empty())
    throw std::invalid_argument("the static orientations never put " + missing +
                                " up: six-position calibration needs every axis once up and once down");

  // Gauss-Newton on theta = (b, s): residual_i = |u_i| - g, u_i = (m_i - b) / s.
  const int n = static_cast<int>(means.size());
  for (r.iterations = 1; r.iterations <= 50; ++r.iterations) {
    Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> Jtr = Eigen::Matrix<double, 6, 1>::Zero();
    for (const Eigen::Vector3d& m : means) {
      const Eigen::Vector3d u = (m - r.bias).cwiseQuotient(r.scale);
      const double un = u.norm();
      Eigen::Matrix<double, 1, 6> J;
      for (int j = 0; j < 3; ++j) {
        J(j) = -(u[j] / un) / r.scale[j];          // d|u| / d b_j
        J(3 + j) = -(u[j] / un) * u[j] / r.scale[j];  // d|u| / d s_j
      }
      JtJ += J.transpose() * J;
      Jtr += J.transpose() * (un - gravity);
    }
    const Eigen::Matrix<double, 6, 1> step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) throw std::invalid_argument("six-position calibration: the fit is ill-conditioned");
    r.bias += step.head<3>();
    r.scale += step.tail<3>();
    if (step.norm() < 1e-12) break;
  }
  double ss = 0.0;
  for (const Eigen::Vector3d& m : means) {
    const double e = (m - r.bias).cwiseQuotient(r.scale).norm() - gravity;
    ss += e * e;
  }
  r.residual_rms_mps2 = std::sqrt(ss / n);
  return r;
}

}  // namespace luxloc
