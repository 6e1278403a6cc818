#include "plugins/playback/fix_csv_source.hpp"

#include <cmath>
#include <limits>

#include "core/common/input_error.hpp"

namespace luxloc {

FixCsvSource::FixCsvSource(const std::string& path)
    : CsvRowSource(path, "playback:fixes", {"t", "x", "y"}),
      t_(col("t")),
      x_(col("x")),
      y_(col("y")),
      sigma_(col("sigma_m")) {}

SensorData FixCsvSource::parse_row(const CsvReader& row) {
  FixSample s;
  s.t = row_time(row, t_);
  s.p_inW = {row.number(x_), row.number(y_)};
  s.sigma_m = row.number_or(sigma_, std::numeric_limits<double>::quiet_NaN());
  if (!std::isnan(s.sigma_m) && !(s.sigma_m > 0.0))
    throw InputError(row.path(), row.line(), "sigma_m", "must be > 0: " + std::string(row.field(sigma_)));
  return s;
}

}  // namespace luxloc
