#include "plugins/output/text_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace luxloc {
namespace {

// Whole rows are buffered until this many bytes are pending (the size stdio used before).
constexpr std::size_t kBufferBytes = 1 << 16;

std::string cause(int err) {
  if (err == EPIPE) return "the reader closed the pipe (EPIPE)";
  if (err == ENOSPC) return "no space left on the device (ENOSPC)";
  if (err == EDQUOT) return "disk quota exceeded (EDQUOT)";
  return std::strerror(err);
}

}  // namespace

TextFile::TextFile(const std::string& path) : path_(path) {
  buffer_.reserve(kBufferBytes);
  if (path == "-") {
    std::fflush(stdout);  // anything printed through stdio before goes first
    fd_ = 1;
  } else {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error("cannot create output file '" + path + "': " + cause(errno));
  }
  struct stat st {};
  regular_ = ::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode);
  if (regular_) committed_ = std::max<off_t>(0, ::lseek(fd_, 0, SEEK_CUR));  // `>>` appends after old text
}

TextFile::~TextFile() {
  if (error_.empty()) {
    try {
      drain();
    } catch (const std::exception&) {
      // Destruction cannot report: flush() is where callers see a failure.
    }
  }
  if (fd_ > 1) ::close(fd_);
}

std::string TextFile::where() const { return is_stdout() ? std::string("stdout") : "'" + path_ + "'"; }

void TextFile::fail(int err, std::size_t bytes_written) {
  // Keep every complete line that reached the disk, cut the partial one.
  std::size_t keep = 0;
  const std::size_t nl = buffer_.rfind('\n', bytes_written == 0 ? std::string::npos : bytes_written - 1);
  if (bytes_written > 0 && nl != std::string::npos) keep = nl + 1;
  lines_on_disk_ += static_cast<std::uint64_t>(std::count(buffer_.begin(), buffer_.begin() + keep, '\n'));
  committed_ += static_cast<std::int64_t>(keep);
  if (regular_) [[maybe_unused]] const int r = ::ftruncate(fd_, committed_);
  buffer_.clear();
  error_ = "cannot write " + where() + ": " + cause(err) + "; the " + std::to_string(lines_on_disk_) +
           " complete lines written before are kept";
  throw std::runtime_error(error_);
}

void TextFile::drain() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(errno, done);
    }
    if (n == 0) fail(EIO, done);
    done += static_cast<std::size_t>(n);
  }
  lines_on_disk_ += static_cast<std::uint64_t>(std::count(buffer_.begin(), buffer_.end(), '\n'));
  committed_ += static_cast<std::int64_t>(buffer_.size());
  buffer_.clear();
}

void TextFile::write(std::string_view text) {
  if (!error_.empty()) throw std::runtime_error(error_);
  if (buffer_.size() + text.size() > kBufferBytes && !buffer_.empty()) drain();
  buffer_.append(text);
  if (buffer_.size() >= kBufferBytes) drain();
}

void TextFile::flush() {
  if (!error_.empty()) throw std::runtime_error(error_);
  drain();
}

}  // namespace luxloc
