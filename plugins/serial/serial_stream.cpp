#include "plugins/serial/serial_stream.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>

#include "core/common/input_error.hpp"
#include "plugins/serial/monotonic_clock.hpp"

namespace luxloc {

SerialStream::SerialStream(SerialStreamOptions options, std::string name, DropCounts& drops)
    : options_(std::move(options)), name_(std::move(name)), drops_(drops), buffer_(4096) {
  int fds[2];
  if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("cannot create the wake-up pipe");
  wake_read_.reset(fds[0]);
  wake_write_.reset(fds[1]);
  try {
    port_.emplace(options_.path, options_.baud);
  } catch (const std::invalid_argument& e) {
    throw InputError("--source", 0, "baud", e.what());
  }
}

void SerialStream::request_stop() {
  stop_.store(true);
  const char b = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_write_.get(), &b, 1);  // full pipe: already woken
}

std::string SerialStream::failure() const {
  std::lock_guard lock(failure_mutex_);
  return failure_;
}

bool SerialStream::reopen(const std::function<void()>& on_reopen) {
  port_.reset();
  while (!stop_.load()) {
    try {
      port_.emplace(options_.path, options_.baud);
      if (options_.report_to_stderr) std::fprintf(stderr, "luxloc: %s: device is back\n", name_.c_str());
      if (on_reopen) on_reopen();
      return true;
    } catch (const std::exception&) {
      // Not back yet: sleep on the wake-up pipe so a stop request is seen at once.
    }
    pollfd p{wake_read_.get(), POLLIN, 0};
    ::poll(&p, 1, static_cast<int>(options_.reopen_interval_s * 1000));
  }
  return false;
}

bool SerialStream::read(const std::function<void()>& on_reopen) {
  while (true) {
    if (stop_.load() || !port_) return false;
    const ReadResult r = port_->read_some(buffer_.data(), buffer_.size(), options_.poll_timeout_ms, wake_read_.get());
    if (r.status == ReadStatus::woken || r.status == ReadStatus::timeout) continue;
    if (r.status == ReadStatus::closed) {
      ++losses_;
      const std::string what = name_ + ": device lost (" + r.error + ")";
      if (options_.on_loss == OnLoss::end) {
        std::lock_guard lock(failure_mutex_);
        failure_ = what;
        port_.reset();
        return false;
      }
      drops_.add("device lost", what);
      if (options_.report_to_stderr) std::fprintf(stderr, "luxloc: %s; waiting for it to come back\n", what.c_str());
      if (!reopen(on_reopen)) return false;
      continue;
    }
    arrival_ = monotonic_now_ns();
    size_ = r.bytes;
    return true;
  }
}

}  // namespace luxloc
