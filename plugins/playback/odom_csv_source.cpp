#include "plugins/playback/odom_csv_source.hpp"

namespace luxloc {

OdomCsvSource::OdomCsvSource(const std::string& path)
    : CsvRowSource(path, "playback:odom", {"t", "dist_m", "dyaw_rad"}),
      t_(col("t")),
      dist_(col("dist_m")),
      dyaw_(col("dyaw_rad")) {}

SensorData OdomCsvSource::parse_row(const CsvReader& row) {
  OdomSample s;
  s.t = row_time(row, t_);
  s.dist_m = row.number(dist_);
  s.dyaw_rad = row.number(dyaw_);
  return s;
}

}  // namespace luxloc
