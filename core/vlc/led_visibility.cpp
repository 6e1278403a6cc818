#include "core/vlc/led_visibility.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/input_error.hpp"

namespace luxloc {

double half_diagonal_fov_rad(const CameraModel& c) {
  double a = 0.0;
  for (const auto& uv : {Eigen::Vector2d(0, 0), Eigen::Vector2d(c.width, 0), Eigen::Vector2d(0, c.height),
                         Eigen::Vector2d(c.width, c.height)}) {
    const Eigen::Vector3d b = c.bearing(uv);
    a = std::max(a, std::atan2(b.head<2>().norm(), b.z()));
  }
  return a;
}

double co_visibility_distance_m(const CameraModel& camera, double dz_m, double max_tilt_rad) {
  const double a = half_diagonal_fov_rad(camera);
  const double cap = 80.0 * 3.14159265358979323846 / 180.0;
  const double far = std::min(a + max_tilt_rad, cap);
  const double near = a - max_tilt_rad;  // may be negative: the near edge passes the zenith
  return std::max(0.0, dz_m) * (std::tan(far) + std::tan(near));
}

void check_frequency_reuse(const LedMap& map, const CameraModel& camera, double device_height_m,
                           const std::string& origin) {
  if (!map.reuses_frequencies()) return;
  // co_visibility_distance_m(camera, dz, 0) = 2 dz tan(a), with the camera's half-diagonal a
  // computed once (it undistorts the corners: too slow to repeat for every pair of copies).
  const double two_tan_a = 2.0 * std::tan(std::min(half_diagonal_fov_rad(camera), 80.0 * 3.14159265358979323846 / 180.0));
  for (const FrequencyClass& fc : map.classes())
    for (std::size_t a = 0; a < fc.members.size(); ++a)
      for (std::size_t b = a + 1; b < fc.members.size(); ++b) {
        const Led& la = map.leds()[static_cast<std::size_t>(fc.members[a])];
        const Led& lb = map.leds()[static_cast<std::size_t>(fc.members[b])];
        const double dz = 0.5 * (la.p_inW.z() + lb.p_inW.z()) - device_height_m;
        const double limit = std::max(0.0, dz) * two_tan_a;
        const double d = (la.p_inW.head<2>() - lb.p_inW.head<2>()).norm();
        if (d < limit) {
          std::ostringstream s;
          s << "LED id " << la.id << " and LED id " << lb.id << " share " << fc.freq_hz << " Hz but are " << d
            << " m apart: a level camera at " << device_height_m << " m sees both at once (needs >= " << limit
            << " m); give one of them another frequency (luxloc calib ledmap plan)";
          throw InputError(origin, 0, "freq_hz", s.str());
        }
      }
}

}  // namespace luxloc
