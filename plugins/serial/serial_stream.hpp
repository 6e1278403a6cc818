#pragma once
// The byte side of a live serial source (serial IMU, UWB): the port, a self-pipe that wakes
// a blocked read on request_stop() from any thread, and the device-lost policy —
//   on_loss=end   read() returns false and failure() says what happened;
//   on_loss=wait  the loss is counted (drops "device lost") and reported on stderr once,
//                 the port is reopened every reopen_interval_s until it comes back or a stop
//                 is requested; `on_reopen` then runs (parser reset, device re-initialised).
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/common/drop_counts.hpp"
#include "core/common/time.hpp"
#include "plugins/serial/serial_port.hpp"

namespace luxloc {

enum class OnLoss { end, wait };

struct SerialStreamOptions {
  std::string path;
  int baud = 115200;
  OnLoss on_loss = OnLoss::end;
  double reopen_interval_s = 0.5;
  int poll_timeout_ms = 200;  // how often a blocked read re-checks the stop flag anyway
  bool report_to_stderr = true;
};

class SerialStream {
 public:
  // Opens the port; throws InputError (field "baud") for an unusable rate and
  // std::runtime_error when the port cannot be opened (exit 1). `name` is the source's, for
  // messages; losses are counted in `drops`.
  SerialStream(SerialStreamOptions options, std::string name, DropCounts& drops);

  // Blocks until bytes arrive: true with them in bytes()/size() and the arrival time
  // (CLOCK_MONOTONIC when read() returned). False once stopped or the device is lost for good.
  bool read(const std::function<void()>& on_reopen);
  const std::uint8_t* bytes() const { return buffer_.data(); }
  std::size_t size() const { return size_; }
  TimeNs arrival() const { return arrival_; }
  // Wire time of one byte (start bit, 8 data bits, stop bit), ns.
  double byte_ns() const { return 10.0 * 1e9 / options_.baud; }

  void request_stop();
  bool stopping() const { return stop_.load(); }
  std::string failure() const;
  std::uint64_t losses() const { return losses_; }
  SerialPort* port() { return port_ ? &*port_ : nullptr; }

 private:
  bool reopen(const std::function<void()>& on_reopen);

  SerialStreamOptions options_;
  std::string name_;
  DropCounts& drops_;
  std::optional<SerialPort> port_;
  UniqueFd wake_read_, wake_write_;
  std::atomic<bool> stop_{false};
  mutable std::mutex failure_mutex_;
  std::string failure_;
  std::vector<std::uint8_t> buffer_;
  std::size_t size_ = 0;
  TimeNs arrival_ = 0;
  std::uint64_t losses_ = 0;
};

}  // namespace luxloc
