#include "plugins/playback/uwb_csv_source.hpp"

#include <limits>

#include "core/common/input_error.hpp"

namespace luxloc {

UwbCsvSource::UwbCsvSource(const std::string& path)
    : CsvRowSource(path, "playback:uwb", {"t", "anchor", "range_m"}),
      t_(col("t")),
      anchor_(col("anchor")),
      range_(col("range_m")),
      aoa_(col("aoa_rad")) {}

SensorData UwbCsvSource::parse_row(const CsvReader& row) {
  UwbSample s;
  s.t = row_time(row, t_);
  const long long id = row.integer(anchor_);
  if (id < std::numeric_limits<int>::min() || id > std::numeric_limits<int>::max())
    throw InputError(row.path(), row.line(), "anchor", "anchor id out of range");
  s.anchor = static_cast<int>(id);
  s.range_m = row.number(range_);
  s.aoa_rad = row.number_or(aoa_, std::numeric_limits<double>::quiet_NaN());
  return s;
}

long long UwbCsvSource::duplicate_key(const SensorData& s) const { return std::get<UwbSample>(s).anchor; }

}  // namespace luxloc
