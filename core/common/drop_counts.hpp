#pragma once
// Counters for what was dropped and why (bad rows, late samples, full queues...).
// Thread-safe; increments are rare (error paths), so a mutex is fine. The first messages
// of each reason (up to kKeptMessages) are kept so the end-of-run report can name the bad
// rows ("imu.csv:57: field 'gx': ...") without holding a message per sample of a flood.
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace luxloc {

class DropCounts {
 public:
  // 20: a dirty file's bad rows are named one by one; beyond that the count says it.
  static constexpr std::size_t kKeptMessages = 20;
  struct Entry {
    std::uint64_t count = 0;
    std::string first_message;
    std::vector<std::string> messages;  // the first kKeptMessages non-empty ones, in order
  };

  void add(const std::string& reason, const std::string& message = {}, std::uint64_t n = 1) {
    std::lock_guard lock(mutex_);
    Entry& e = entries_[reason];
    if (e.count == 0) e.first_message = message;
    if (!message.empty() && e.messages.size() < kKeptMessages) e.messages.push_back(message);
    e.count += n;
  }
  std::uint64_t count(const std::string& reason) const {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(reason);
    return it == entries_.end() ? 0 : it->second.count;
  }
  std::uint64_t total() const {
    std::lock_guard lock(mutex_);
    std::uint64_t n = 0;
    for (const auto& [k, e] : entries_) n += e.count;
    return n;
  }
  std::map<std::string, Entry> snapshot() const {
    std::lock_guard lock(mutex_);
    return entries_;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

}  // namespace luxloc
