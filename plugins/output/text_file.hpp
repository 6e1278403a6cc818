#pragma once
// A buffered text output: a file, or stdout for "-", written through write(2) from a
// 64 KiB buffer of our own (not stdio), so a failure is seen where it happens and the file
// can be left clean:
//   - the buffer only ever holds whole write() calls (a pose row, a header line), and when
//     a write fails (disk full, I/O error) a regular file is cut back (ftruncate) to the
//     last complete line that reached the disk: every row in the file is intact;
//   - after a failure every later write() throws at once (nothing is half-appended later);
//   - a closed pipe (`luxloc run --out - | head`) is EPIPE, reported as "the reader closed
//     the pipe"; SIGPIPE is ignored by main(), so the process is not killed by it.
#include <cstdint>
#include <string>
#include <string_view>

namespace luxloc {

class TextFile {
 public:
  // Throws std::runtime_error (exit 1: an I/O failure) when the file cannot be created
  // (missing folder, no permission, read-only file system), naming the path and the cause.
  explicit TextFile(const std::string& path);
  ~TextFile();
  TextFile(const TextFile&) = delete;
  TextFile& operator=(const TextFile&) = delete;

  // Throws std::runtime_error (exit 1: I/O error, disk full, closed pipe) when the write
  // fails; the file then holds every complete line written before.
  void write(std::string_view text);
  void flush();
  const std::string& path() const { return path_; }
  bool is_stdout() const { return fd_ == 1; }
  // Complete lines that reached the file (counted at each successful flush of the buffer).
  std::uint64_t lines_on_disk() const { return lines_on_disk_; }
  bool failed() const { return !error_.empty(); }

 private:
  void drain();  // writes the whole buffer or throws
  [[noreturn]] void fail(int err, std::size_t bytes_written);
  std::string where() const;

  std::string path_;
  int fd_ = -1;
  bool regular_ = false;        // a regular file (can be cut back after a failure)
  std::int64_t committed_ = 0;  // file offset after the last complete line on disk
  std::uint64_t lines_on_disk_ = 0;
  std::string buffer_;
  std::string error_;  // the first failure; later writes repeat it
};

}  // namespace luxloc
