#pragma once
// A byte-stream protocol of a serial IMU: bytes in, samples out. Parsers resynchronise by
// themselves after garbage and count what they drop (in the DropCounts they were given,
// under the reasons of serial_drop::).
//
// Timestamps (arrival): the caller gives the CLOCK_MONOTONIC time at which the read() that
// delivered the chunk returned (t_end, taken as the arrival of the chunk's last byte) and
// the time one byte takes on the wire (10 bits / baud). A sample is stamped with the arrival
// of its own last byte: t_end - (bytes after it in the chunk) * byte_ns. Samples that share
// a read are thereby spread as they were sent instead of collapsing on one time.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/common/drop_counts.hpp"
#include "core/common/samples.hpp"

namespace luxloc {

namespace serial_drop {
inline constexpr const char* kSkippedBytes = "skipped bytes";        // garbage between packets / lines
inline constexpr const char* kBadChecksum = "bad checksum";          // header and type right, checksum wrong
inline constexpr const char* kIncompleteSample = "incomplete sample";  // a cycle without acc or gyro
inline constexpr const char* kBadLine = "bad line";                  // CSV: unparseable, too few fields
inline constexpr const char* kLongLine = "line too long";            // CSV: no newline in max_line bytes
inline constexpr const char* kDeviceLost = "device lost";            // on_loss=wait: the port went away
}  // namespace serial_drop

class ImuStreamParser {
 public:
  explicit ImuStreamParser(DropCounts& drops) : drops_(drops) {}
  virtual ~ImuStreamParser() = default;
  ImuStreamParser(const ImuStreamParser&) = delete;
  ImuStreamParser& operator=(const ImuStreamParser&) = delete;

  // Appends the samples completed by these bytes to `out`.
  virtual void feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
                    std::vector<ImuSample>& out) = 0;
  // Forget partial data (after the port was reopened).
  virtual void reset() = 0;

 protected:
  DropCounts& drops_;
};

}  // namespace luxloc
