#pragma once
// A serial port (termios) in raw mode: 8N1, no flow control, no echo, no line editing, at
// any standard baud rate. RAII: the descriptor closes with the object. Reads wait with
// poll() so that a second descriptor (a self-pipe) can wake them up, and report a hang-up
// (USB adapter pulled, pseudo-terminal's other side closed) as ReadStatus::closed.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace luxloc {

// Owns a file descriptor.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }
  int get() const { return fd_; }
  int release() {
    const int f = fd_;
    fd_ = -1;
    return f;
  }
  void reset(int fd = -1);
  explicit operator bool() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

enum class ReadStatus { data, timeout, woken, closed };

struct ReadResult {
  ReadStatus status = ReadStatus::timeout;
  std::size_t bytes = 0;
  std::string error;  // for closed: what the system said
};

class SerialPort {
 public:
  // Opens `path` and configures it. Throws std::invalid_argument for a baud rate that is
  // not a standard one, std::runtime_error (with the system's reason) when the port cannot
  // be opened or configured.
  SerialPort(const std::string& path, int baud);

  // Waits up to timeout_ms for data, or for wake_fd (if >= 0) to become readable; reads at
  // most `capacity` bytes.
  ReadResult read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms, int wake_fd = -1);
  // Writes everything (for tests and device configuration); throws std::runtime_error.
  void write_all(const std::uint8_t* data, std::size_t size);

  const std::string& path() const { return path_; }
  int baud() const { return baud_; }
  int fd() const { return fd_.get(); }

  static bool is_standard_baud(int baud);
  static std::vector<int> standard_bauds();

 private:
  std::string path_;
  int baud_ = 0;
  UniqueFd fd_;
};

}  // namespace luxloc
