#pragma once
// Text-line protocol of a serial IMU: one sample per line, numbers separated by commas,
// semicolons, tabs or spaces, lines ended by \n (a \r before it is ignored), '#' lines are
// comments. Column order is configurable (names t, ax, ay, az, gx, gy, gz, mx, my, mz; '_'
// skips a column); without an explicit order, a header line of known names sets it, else
// SPEC.md's imu.csv order t,ax,ay,az,gx,gy,gz,mx,my,mz applies. The magnetometer columns are
// optional per line (absent or empty: no magnetometer in that sample).
// Units are converted to SI with per-sensor factors (acc_unit g, gyro_unit dps, ...).
//
// Time: `arrival` (default) stamps a line with the arrival of its newline (see
// ImuStreamParser); `device` uses the line's t column mapped onto the arrival clock with
// the smallest arrival-minus-device offset seen so far (the least-delayed line), re-anchored
// when the device clock jumps back or lags by more than a second (device reset).
// Bad lines (too few fields, a non-number, a non-finite value) are skipped and counted.
#include <string>

#include "plugins/serial/imu_stream_parser.hpp"

namespace luxloc {

struct CsvLineOptions {
  std::vector<std::string> columns;  // empty: header line or SPEC order
  double acc_to_mps2 = 1.0;          // 9.80665 for g
  double gyro_to_rps = 1.0;          // pi/180 for deg/s
  double mag_to_ut = 1.0;            // 100 for gauss, 0.1 for milligauss
  bool device_time = false;
  double time_to_s = 1.0;            // 1e-3 for a millisecond t column
  std::size_t max_line = 512;

  // Unit names: acc mps2|g, gyro rps|dps, mag ut|gauss|mgauss|nt, time s|ms|us.
  // Throw std::invalid_argument for an unknown name.
  static double acc_unit(const std::string& name);
  static double gyro_unit(const std::string& name);
  static double mag_unit(const std::string& name);
  static double time_unit(const std::string& name);
  // "t:ax:ay:az:gx:gy:gz" (':' separated, since ',' separates --source options); checks
  // the names and that ax..gz are present; throws std::invalid_argument.
  static std::vector<std::string> parse_columns(const std::string& text);
};

class CsvLineParser final : public ImuStreamParser {
 public:
  CsvLineParser(DropCounts& drops, const CsvLineOptions& options = {});
  void feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
            std::vector<ImuSample>& out) override;
  void reset() override;
  std::uint64_t lines() const { return lines_; }
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  void set_columns(const std::vector<std::string>& names);
  void on_line(std::string_view line, TimeNs t_arrival, std::vector<ImuSample>& out);

  CsvLineOptions options_;
  std::vector<std::string> columns_;
  int col_[10] = {};  // t ax ay az gx gy gz mx my mz -> field index or -1
  std::string line_;
  bool discarding_ = false;  // inside an over-long line: drop up to the next newline
  std::uint64_t lines_ = 0;
  bool have_offset_ = false;
  TimeNs offset_ = 0;  // arrival - device
};

}  // namespace luxloc
