#include "plugins/serial/imu_axis_map.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace luxloc {

ImuAxisMap ImuAxisMap::parse(const std::string& text) {
  const std::string why = "axes '" + text + "': expected three signed axes such as +x+y+z or +y-x+z";
  if (text.size() != 6) throw std::invalid_argument(why);
  ImuAxisMap m;
  m.M_.setZero();
  for (int row = 0; row < 3; ++row) {
    const char sign = text[2 * row], axis = text[2 * row + 1];
    if ((sign != '+' && sign != '-') || axis < 'x' || axis > 'z') throw std::invalid_argument(why);
    m.M_(row, axis - 'x') = sign == '+' ? 1.0 : -1.0;
  }
  if (std::abs(m.M_.determinant() - 1.0) > 1e-9)
    throw std::invalid_argument("axes '" + text + "' is not a rotation (an axis repeats, or the mapping mirrors)");
  return m;
}

ImuSample ImuAxisMap::apply(const ImuSample& s) const {
  ImuSample o = s;
  o.acc_inB = M_ * s.acc_inB;
  o.gyro_inB = M_ * s.gyro_inB;
  if (s.has_mag) o.mag_inB = M_ * s.mag_inB;
  return o;
}

}  // namespace luxloc
