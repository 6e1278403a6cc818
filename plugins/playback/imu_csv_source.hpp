#pragma once
// imu.csv playback (SPEC.md): t,ax,ay,az,gx,gy,gz[,mx,my,mz], body frame (FLU), SI units,
// magnetometer in microtesla. The magnetometer is optional per file (all three columns in
// the header) and per row (empty fields -> has_mag = false).
#include "plugins/playback/csv_row_source.hpp"

namespace luxloc {

class ImuCsvSource : public CsvRowSource {
 public:
  // Throws InputError when a required column is missing or only some of mx,my,mz exist.
  explicit ImuCsvSource(const std::string& path);
  bool has_mag_columns() const { return c_[6] >= 0; }

 protected:
  SensorData parse_row(const CsvReader& row) override;

 private:
  int t_ = -1;
  int c_[9] = {};  // ax ay az gx gy gz mx my mz
};

}  // namespace luxloc
