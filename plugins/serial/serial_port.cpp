#include "plugins/serial/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace luxloc {
namespace {

struct BaudEntry {
  int baud;
  speed_t code;
};
// Every rate termios names on Linux.
constexpr BaudEntry kBauds[] = {
    {50, B50},           {75, B75},           {110, B110},         {134, B134},         {150, B150},
    {200, B200},         {300, B300},         {600, B600},         {1200, B1200},       {1800, B1800},
    {2400, B2400},       {4800, B4800},       {9600, B9600},       {19200, B19200},     {38400, B38400},
    {57600, B57600},     {115200, B115200},   {230400, B230400},   {460800, B460800},   {500000, B500000},
    {576000, B576000},   {921600, B921600},   {1000000, B1000000}, {1152000, B1152000}, {1500000, B1500000},
    {2000000, B2000000}, {2500000, B2500000}, {3000000, B3000000}, {3500000, B3500000}, {4000000, B4000000},
};

std::string system_error(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

UniqueFd& UniqueFd::operator=(UniqueFd&& o) noexcept {
  if (this != &o) reset(o.release());
  return *this;
}

void UniqueFd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

bool SerialPort::is_standard_baud(int baud) {
  for (const BaudEntry& e : kBauds)
    if (e.baud == baud) return true;
  return false;
}

std::vector<int> SerialPort::standard_bauds() {
  std::vector<int> v;
  for (const BaudEntry& e : kBauds) v.push_back(e.baud);
  return v;
}

SerialPort::SerialPort(const std::string& path, int baud) : path_(path), baud_(baud) {
  speed_t code = 0;
  bool known = false;
  for (const BaudEntry& e : kBauds)
    if (e.baud == baud) {
      code = e.code;
      known = true;
    }
  if (!known) throw std::invalid_argument("baud rate " + std::to_string(baud) + " is not a standard rate");

  // Non-blocking so open() does not wait for carrier detect; reads go through poll().
  fd_.reset(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd_) throw std::runtime_error(system_error("cannot open serial port '" + path + "'"));
  termios tio{};
  if (tcgetattr(fd_.get(), &tio) != 0)
    throw std::runtime_error(system_error("'" + path + "' is not a serial port (tcgetattr)"));
  cfmakeraw(&tio);                   // 8 data bits, no parity, no echo, no line editing
  tio.c_cflag |= CLOCAL | CREAD;     // ignore modem lines, enable the receiver
  tio.c_cflag &= ~(CSTOPB | CRTSCTS);  // one stop bit, no hardware flow control
  tio.c_iflag &= ~(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (cfsetispeed(&tio, code) != 0 || cfsetospeed(&tio, code) != 0 || tcsetattr(fd_.get(), TCSANOW, &tio) != 0)
    throw std::runtime_error(system_error("cannot configure serial port '" + path + "'"));
  tcflush(fd_.get(), TCIFLUSH);  // whatever sat in the driver's buffer is stale
}

ReadResult SerialPort::read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms, int wake_fd) {
  ReadResult r;
  pollfd fds[2] = {{fd_.get(), POLLIN, 0}, {wake_fd, POLLIN, 0}};
  const int n = ::poll(fds, wake_fd >= 0 ? 2 : 1, timeout_ms);
  if (n < 0) {
    if (errno == EINTR) return r;  // a signal: the caller looks at its stop flag
    r.status = ReadStatus::closed;
    r.error = system_error("poll");
    return r;
  }
  if (n == 0) return r;
  if (wake_fd >= 0 && (fds[1].revents & POLLIN)) {
    r.status = ReadStatus::woken;
    return r;
  }
  if (fds[0].revents & (POLLIN | POLLHUP | POLLERR | POLLNVAL)) {
    // Read even on POLLHUP: the last bytes the writer sent may still be buffered.
    const ssize_t got = ::read(fd_.get(), buffer, capacity);
    if (got > 0) {
      r.status = ReadStatus::data;
      r.bytes = static_cast<std::size_t>(got);
      return r;
    }
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) return r;
    r.status = ReadStatus::closed;
    r.error = got == 0 ? std::string("end of file (the device or the other side went away)")
                       : system_error("read");
    if (got < 0 && errno == EIO) r.error = "input/output error (the device or the other side went away)";
  }
  return r;
}

void SerialPort::write_all(const std::uint8_t* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd_.get(), data, size);
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) {
        pollfd p{fd_.get(), POLLOUT, 0};
        ::poll(&p, 1, 100);
        continue;
      }
      throw std::runtime_error(system_error("write to '" + path_ + "'"));
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

}  // namespace luxloc
