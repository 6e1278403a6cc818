#pragma once
// `serial-imu:/dev/ttyX[,baud=..,protocol=csv|witmotion,...]` (SPEC.md "Source kinds"): a
// live IMU on a serial port. next() blocks until a sample arrives; request_stop() (any
// thread) wakes it through a self-pipe and makes it return false.
//
// Timestamps: CLOCK_MONOTONIC at arrival (plugins/serial/monotonic_clock.hpp), back-dated
// within a read by the wire time of the bytes after the sample (ImuStreamParser), then made
// strictly increasing (+1 us when two samples would share or reverse a time).
//
// Loss of the device (USB adapter pulled, pty writer gone: hang-up, EOF or EIO):
//   on_loss=end  (default) next() returns false and failure() says what happened: the run
//                ends cleanly and the CLI exits 1 ("device lost");
//   on_loss=wait the loss is counted (drops "device lost") and reported on stderr once, the
//                port is reopened every reopen_interval_s until it comes back or a stop is
//                requested; samples resume on the same timeline.
// Options from the --source spec (make_serial_imu_source): baud (standard rates),
// protocol, axes (ImuAxisMap), on_loss, and per protocol:
//   witmotion: acc_range_g, gyro_range_dps, mag_scale (uT per count)
//   csv:       columns (t:ax:ay:az:gx:gy:gz[:mx:my:mz], '_' skips), acc_unit (mps2|g),
//              gyro_unit (rps|dps), mag_unit (ut|gauss|mgauss|nt), time (arrival|device),
//              time_unit (s|ms|us)
#include <deque>
#include <memory>

#include "core/pipeline/source.hpp"
#include "plugins/serial/csv_line_parser.hpp"
#include "plugins/serial/imu_axis_map.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/serial/serial_stream.hpp"
#include "plugins/serial/witmotion_parser.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

enum class SerialProtocol { csv, witmotion };

struct SerialImuOptions {
  std::string path;
  int baud = 115200;
  SerialProtocol protocol = SerialProtocol::csv;
  WitMotionOptions witmotion;
  CsvLineOptions csv;
  ImuAxisMap axes;
  SensorLimits limits;  // samples beyond them are dropped as "out of range"
  OnLoss on_loss = OnLoss::end;
  double reopen_interval_s = 0.5;
  int poll_timeout_ms = 200;  // how often a blocked next() re-checks the stop flag anyway
  bool report_to_stderr = true;

  // From a parsed --source spec; throws InputError (field = the key) for bad values.
  static SerialImuOptions from_spec(const SourceSpec& spec);
  SerialStreamOptions stream() const;
};

class SerialImuSource final : public Source {
 public:
  // Opens the port; throws std::runtime_error when it cannot (exit 1).
  explicit SerialImuSource(SerialImuOptions options);
  ~SerialImuSource() override = default;

  std::string name() const override { return "serial-imu:" + options_.path; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  std::string failure() const override;

  std::uint64_t samples() const { return samples_; }
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t losses() const { return stream_.losses(); }  // times the device went away
  std::uint64_t retimed() const { return retimed_; }  // stamps pushed forward to stay increasing
  const SerialImuOptions& options() const { return options_; }

 private:
  std::unique_ptr<ImuStreamParser> make_parser();

  SerialImuOptions options_;
  SerialStream stream_;
  std::unique_ptr<ImuStreamParser> parser_;
  std::deque<ImuSample> ready_;
  std::vector<ImuSample> parsed_;
  TimeNs last_t_ = 0;
  std::uint64_t samples_ = 0, bytes_ = 0, retimed_ = 0;
};

// The `serial-imu` kind for make_live_source.
SourcePtr make_serial_imu_source(const SourceSpec& spec);

}  // namespace luxloc
