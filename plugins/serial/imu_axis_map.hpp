#pragma once
// Maps a sensor's own axes onto luxloc's body frame (FLU, SPEC.md). Written as three signed
// sensor axes, the sources of body x, y and z: "+x+y+z" (identity), "+y-x+z" (body x = sensor
// y, body y = -sensor x, body z = sensor z). Must be a rotation (a permutation with
// determinant +1), so a mirrored mount is caught before it silently corrupts the attitude.
#include <Eigen/Core>
#include <string>

#include "core/common/samples.hpp"

namespace luxloc {

class ImuAxisMap {
 public:
  ImuAxisMap() = default;  // identity
  // Throws std::invalid_argument naming the problem.
  static ImuAxisMap parse(const std::string& text);
  Eigen::Vector3d apply(const Eigen::Vector3d& v_inSensor) const { return M_ * v_inSensor; }
  ImuSample apply(const ImuSample& s) const;
  bool identity() const { return M_.isIdentity(0); }
  const Eigen::Matrix3d& matrix() const { return M_; }  // body = M * sensor

 private:
  Eigen::Matrix3d M_ = Eigen::Matrix3d::Identity();
};

}  // namespace luxloc
