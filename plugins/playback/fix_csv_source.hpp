#pragma once
// fixes.csv playback (SPEC.md): t,x,y[,sigma_m] — any absolute 2-D position fix in the
// world frame. sigma_m empty or absent -> NaN (the filter's default applies); <= 0 is a bad row.
#include "plugins/playback/csv_row_source.hpp"

namespace luxloc {

class FixCsvSource : public CsvRowSource {
 public:
  explicit FixCsvSource(const std::string& path);

 protected:
  SensorData parse_row(const CsvReader& row) override;

 private:
  int t_ = -1, x_ = -1, y_ = -1, sigma_ = -1;
};

}  // namespace luxloc
