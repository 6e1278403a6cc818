#pragma once
// A pseudo-terminal pair made by socat for the serial tests: writes to a() come out of b()
// (and back). Started with a folder of its own, stopped (SIGTERM, reaped) on destruction.
// available() is false when socat is not installed: tests then skip with a WARN.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

extern char** environ;

namespace luxloc::test {

class SocatPair {
 public:
  static bool available() {
    for (const char* dir : {"/usr/bin/", "/bin/", "/usr/local/bin/"})
      if (::access((std::string(dir) + "socat").c_str(), X_OK) == 0) return true;
    return false;
  }

  explicit SocatPair(const std::filesystem::path& dir) : dir_(dir) { start(); }
  ~SocatPair() { stop(); }
  SocatPair(const SocatPair&) = delete;
  SocatPair& operator=(const SocatPair&) = delete;

  std::string a() const { return (dir_ / "a").string(); }
  std::string b() const { return (dir_ / "b").string(); }
  bool running() const { return pid_ > 0; }

  // Starts socat (again) with the same link names; true once both links exist.
  bool start() {
    stop();
    std::filesystem::remove(dir_ / "a");
    std::filesystem::remove(dir_ / "b");
    const std::string la = "pty,raw,echo=0,link=" + a(), lb = "pty,raw,echo=0,link=" + b();
    const std::string log = (dir_ / "socat.log").string();
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    char* argv[] = {const_cast<char*>("socat"), const_cast<char*>("-d"), const_cast<char*>("-d"),
                    const_cast<char*>(la.c_str()), const_cast<char*>(lb.c_str()), nullptr};
    const int rc = posix_spawnp(&pid_, "socat", &fa, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
      pid_ = -1;
      return false;
    }
    for (int i = 0; i < 300; ++i) {
      if (std::filesystem::exists(dir_ / "a") && std::filesystem::exists(dir_ / "b")) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  // Kills socat (the "device" disappears) and reaps it.
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }

  // Waits (up to timeout) until a process other than socat and this one holds b() open:
  // the program under test has opened the port. A fixed sleep instead loses the bytes
  // written before the open when the machine is loaded (sanitizer builds on 2 cores).
  bool wait_b_opened(std::chrono::milliseconds timeout) const {
    std::error_code ec;
    const std::filesystem::path target = std::filesystem::canonical(b(), ec);
    if (ec) return false;
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      for (const auto& proc : std::filesystem::directory_iterator("/proc", ec)) {
        const std::string name = proc.path().filename().string();
        if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = static_cast<pid_t>(std::stol(name));
        if (pid == pid_ || pid == ::getpid()) continue;
        std::error_code fec;
        for (const auto& fd : std::filesystem::directory_iterator(proc.path() / "fd", fec)) {
          std::error_code lec;
          if (std::filesystem::read_symlink(fd.path(), lec) == target) return true;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  // Waits (up to timeout) for socat to exit by itself; true when it did.
  bool wait_exit(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (pid_ > 0 && std::chrono::steady_clock::now() < end) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return pid_ <= 0;
  }

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

}  // namespace luxloc::test
