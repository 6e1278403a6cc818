#include "plugins/v4l2/v4l2_io.hpp"

#include <fcntl.h>
#include <libv4l2.h>
#include <sys/mman.h>

namespace luxloc {
namespace {

class LibV4l2Io final : public V4l2Io {
 public:
  int open(const std::string& path, int flags) override { return ::open(path.c_str(), flags); }
  int fd_open(int fd) override { return v4l2_fd_open(fd, 0); }
  int close(int fd) override { return v4l2_close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override { return v4l2_ioctl(fd, request, arg); }
  void* mmap(std::size_t length, int fd, std::int64_t offset) override {
    return v4l2_mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
  }
  int munmap(void* start, std::size_t length) override { return v4l2_munmap(start, length); }
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override { return ::poll(fds, count, timeout_ms); }
};

}  // namespace

std::shared_ptr<V4l2Io> libv4l2_io() {
  static const std::shared_ptr<V4l2Io> io = std::make_shared<LibV4l2Io>();
  return io;
}

}  // namespace luxloc
