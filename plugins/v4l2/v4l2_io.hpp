#pragma once
// The seam between the V4L2 camera code and the device: every call V4l2Camera makes to the
// kernel (through libv4l2) goes through this interface. libv4l2_io() is the real one; the
// tests drive the same V4l2Camera / V4l2CameraSource code with an ioctl-level fake device
// (tests/plugins/v4l2/fake_v4l2_device.*): format negotiation, mmap buffer cycling, driver
// time stamps, controls, EBUSY, ENODEV, poll timeouts, short buffers. Calls return what the
// system calls return (-1 / MAP_FAILED with errno set).
#include <poll.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace luxloc {

class V4l2Io {
 public:
  virtual ~V4l2Io() = default;
  // open(2) of the device node (no libv4l2 yet: a file that is no V4L2 device gets our
  // message, not libv4l2's).
  virtual int open(const std::string& path, int flags) = 0;
  // v4l2_fd_open: libv4l2 takes a descriptor over (its format emulation, its ioctl wrapper).
  virtual int fd_open(int fd) = 0;
  // v4l2_close (on a descriptor libv4l2 does not own: close(2)).
  virtual int close(int fd) = 0;
  // v4l2_ioctl (on a descriptor libv4l2 does not own: ioctl(2)).
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  // v4l2_mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset).
  virtual void* mmap(std::size_t length, int fd, std::int64_t offset) = 0;
  virtual int munmap(void* start, std::size_t length) = 0;
  // poll(2) on the device and, beside it, the caller's own descriptors (a wake-up pipe).
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

// The real device through libv4l2 (one shared, stateless instance).
std::shared_ptr<V4l2Io> libv4l2_io();

}  // namespace luxloc
