#pragma once
// uwb.csv playback (SPEC.md): t,anchor,range_m[,aoa_rad]. range_m is the measured 3-D
// anchor->device distance; aoa_rad the world bearing of the device seen from the anchor
// (empty or absent -> NaN). Several anchors may share one time stamp; only a repeated
// (t, anchor) pair is a duplicate.
#include "plugins/playback/csv_row_source.hpp"

namespace luxloc {

class UwbCsvSource : public CsvRowSource {
 public:
  explicit UwbCsvSource(const std::string& path);
  bool has_aoa_column() const { return aoa_ >= 0; }

 protected:
  SensorData parse_row(const CsvReader& row) override;
  long long duplicate_key(const SensorData& s) const override;

 private:
  int t_ = -1, anchor_ = -1, range_ = -1, aoa_ = -1;
};

}  // namespace luxloc
