#pragma once
// odom.csv playback (SPEC.md): t,dist_m,dyaw_rad — wheel / step odometry increments since
// the previous row.
#include "plugins/playback/csv_row_source.hpp"

namespace luxloc {

class OdomCsvSource : public CsvRowSource {
 public:
  explicit OdomCsvSource(const std::string& path);

 protected:
  SensorData parse_row(const CsvReader& row) override;

 private:
  int t_ = -1, dist_ = -1, dyaw_ = -1;
};

}  // namespace luxloc
