#pragma once
// `uwb:/dev/ttyX[,baud=..,protocol=dwm1001|tof-aoa,...]` (SPEC.md "Source kinds"): a UWB
// tag or base station on a serial port. next() blocks until a measurement arrives;
// request_stop() (any thread) wakes it through a self-pipe.
//   protocol=dwm1001 (default) a DWM1001 tag's shell in `lec` mode (Dwm1001Parser):
//                    ranges with the anchor positions the tag reports; position=1 also
//                    emits the tag's own POS as a position fix (min_quality=50).
//                    init=lec sends "\r\r" then "lec\r" after opening (enters the shell
//                    and starts the reports; do not use it when the tag already reports:
//                    `lec` toggles).
//   protocol=tof-aoa <anchor>,<range_m>[,<aoa_rad>] lines (TofAoaLineParser).
// Timestamps: CLOCK_MONOTONIC at arrival of each line (back-dated by the wire time of the
// bytes after it), never decreasing; the ranges of one DWM1001 line share its time.
// Loss of the device: on_loss=end (default: next() returns false, failure() says why,
// the CLI exits 1) or on_loss=wait (counted under "device lost", reopened every
// reopen_interval_s), as serial-imu does.
#include <deque>
#include <memory>

#include "core/pipeline/source.hpp"
#include "plugins/serial/serial_imu_source.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/serial/serial_stream.hpp"
#include "plugins/source_spec.hpp"
#include "plugins/uwb/dwm1001_parser.hpp"

namespace luxloc {

enum class UwbProtocol { dwm1001, tof_aoa };

struct UwbSerialOptions {
  std::string path;
  int baud = 115200;
  UwbProtocol protocol = UwbProtocol::dwm1001;
  Dwm1001Options dwm1001;
  SensorLimits limits;  // ranges (and fixes) beyond them are dropped as "out of range"
  bool init_lec = false;
  OnLoss on_loss = OnLoss::end;
  double reopen_interval_s = 0.5;
  int poll_timeout_ms = 200;
  bool report_to_stderr = true;

  // From a parsed --source spec; throws InputError (field = the key) for bad values.
  static UwbSerialOptions from_spec(const SourceSpec& spec);
  SerialStreamOptions stream() const { return {path, baud, on_loss, reopen_interval_s, poll_timeout_ms, report_to_stderr}; }
};

class UwbSerialSource final : public Source {
 public:
  // Opens the port; throws std::runtime_error when it cannot (exit 1).
  explicit UwbSerialSource(UwbSerialOptions options);

  std::string name() const override { return "uwb:" + options_.path; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  std::string failure() const override;

  std::uint64_t samples() const { return samples_; }
  std::uint64_t losses() const { return stream_.losses(); }
  const UwbSerialOptions& options() const { return options_; }

 private:
  std::unique_ptr<UwbStreamParser> make_parser();
  void send_init();

  UwbSerialOptions options_;
  SerialStream stream_;
  std::unique_ptr<UwbStreamParser> parser_;
  std::deque<SensorData> ready_;
  std::vector<SensorData> parsed_;
  TimeNs last_t_ = 0;
  std::uint64_t samples_ = 0;
};

// The `uwb` kind for make_live_source.
SourcePtr make_uwb_serial_source(const SourceSpec& spec);

}  // namespace luxloc
