#pragma once
// A small tmpfs mounted on a scratch folder for the full-disk tests (mount(2) needs root:
// available() is false otherwise and the tests fall back to /dev/full or skip with a WARN).
// Unmounted (lazily, MNT_DETACH) on destruction.
#include <sys/mount.h>

#include <filesystem>
#include <string>

namespace luxloc::test {

class SmallTmpfs {
 public:
  SmallTmpfs(const std::filesystem::path& dir, const std::string& size, bool read_only = false) : dir_(dir) {
    std::filesystem::create_directories(dir_);
    const std::string opts = "size=" + size;
    mounted_ = ::mount("tmpfs", dir_.c_str(), "tmpfs", read_only ? MS_RDONLY : 0, opts.c_str()) == 0;
  }
  ~SmallTmpfs() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  SmallTmpfs(const SmallTmpfs&) = delete;
  SmallTmpfs& operator=(const SmallTmpfs&) = delete;

  bool available() const { return mounted_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  bool mounted_ = false;
};

}  // namespace luxloc::test
