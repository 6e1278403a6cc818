#pragma once
// A buffered text output: a file, or stdout for "-". Used by the pose file sinks; writes
// go through stdio's buffer (64 KiB) and reach the file on flush() or destruction.
#include <cstdio>
#include <string>
#include <string_view>

namespace luxloc {

class TextFile {
 public:
  // Throws InputError (exit 2: a bad --out argument) when the file cannot be created.
  explicit TextFile(const std::string& path);
  ~TextFile();
  TextFile(const TextFile&) = delete;
  TextFile& operator=(const TextFile&) = delete;

  // Throws std::runtime_error (exit 1: I/O error, disk full) when the write fails.
  void write(std::string_view text);
  void flush();
  const std::string& path() const { return path_; }
  bool is_stdout() const { return file_ == stdout; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

}  // namespace luxloc
