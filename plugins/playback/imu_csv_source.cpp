#include "plugins/playback/imu_csv_source.hpp"

#include <cmath>
#include <limits>

#include "core/common/input_error.hpp"

namespace luxloc {

ImuCsvSource::ImuCsvSource(const std::string& path)
    : CsvRowSource(path, "playback:imu", {"t", "ax", "ay", "az", "gx", "gy", "gz"}) {
  t_ = col("t");
  const char* names[9] = {"ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz"};
  for (int i = 0; i < 9; ++i) c_[i] = col(names[i]);
  const int n_mag = (c_[6] >= 0) + (c_[7] >= 0) + (c_[8] >= 0);
  if (n_mag != 0 && n_mag != 3)
    throw InputError(path, 1, "mx,my,mz", "the magnetometer needs all three columns (or none)");
}

SensorData ImuCsvSource::parse_row(const CsvReader& row) {
  ImuSample s;
  s.t = row_time(row, t_);
  s.acc_inB = {row.number(c_[0]), row.number(c_[1]), row.number(c_[2])};
  s.gyro_inB = {row.number(c_[3]), row.number(c_[4]), row.number(c_[5])};
  if (has_mag_columns()) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    s.mag_inB = {row.number_or(c_[6], nan), row.number_or(c_[7], nan), row.number_or(c_[8], nan)};
    s.has_mag = s.mag_inB.allFinite();
    if (!s.has_mag) s.mag_inB.setZero();
  }
  return s;
}

}  // namespace luxloc
