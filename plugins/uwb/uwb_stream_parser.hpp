#pragma once
// A text protocol of a UWB device on a serial port: bytes in, samples out (UwbSample per
// range, FixSample for a position the device computed itself). Lines end with \n (a \r
// before it is ignored); a line is stamped with the arrival of its newline, back-dated by
// the wire time of the bytes after it in the chunk (as ImuStreamParser does). Bad lines
// are skipped and counted under uwb_drop:: reasons.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/common/drop_counts.hpp"
#include "core/common/samples.hpp"

namespace luxloc {

namespace uwb_drop {
inline constexpr const char* kBadLine = "bad line";            // unparseable / inconsistent record
inline constexpr const char* kBadPosition = "bad position";    // POS block unusable (ranges kept)
inline constexpr const char* kLongLine = "line too long";      // no newline within max_line bytes
inline constexpr const char* kDeviceLost = "device lost";      // on_loss=wait: the port went away
}  // namespace uwb_drop

class UwbStreamParser {
 public:
  explicit UwbStreamParser(DropCounts& drops, std::size_t max_line = 1024) : drops_(drops), max_line_(max_line) {}
  virtual ~UwbStreamParser() = default;
  UwbStreamParser(const UwbStreamParser&) = delete;
  UwbStreamParser& operator=(const UwbStreamParser&) = delete;

  void feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns, std::vector<SensorData>& out);
  void reset() {
    line_.clear();
    discarding_ = false;
  }
  std::uint64_t lines() const { return lines_; }

 protected:
  // One complete line without its terminator (trimmed, non-empty).
  virtual void on_line(std::string_view line, TimeNs t, std::vector<SensorData>& out) = 0;
  DropCounts& drops_;

 private:
  std::size_t max_line_;
  std::string line_;
  bool discarding_ = false;
  std::uint64_t lines_ = 0;
};

}  // namespace luxloc
