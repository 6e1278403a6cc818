#pragma once
// Base of the file-playback sources: streams a SPEC.md CSV one row per next() (never the
// whole file: sessions can be long), and applies the playback bad-input policy: a row that
// cannot be used (unparseable or non-finite number, too few fields, time going backwards,
// duplicated timestamp) is skipped and counted in drops() under a reason, keeping the first
// message ("imu.csv:12: field 'gx': not a number: 'abc'"), and reading carries on.
// A row that parses but holds a value its sensor cannot measure (core/common/sensor_limits)
// is counted as "out of range" before the time checks, so of two rows sharing a time stamp
// the plausible one is kept.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/common/csv_reader.hpp"
#include "core/common/sensor_limits.hpp"
#include "core/pipeline/source.hpp"

namespace luxloc {

// DropCounts reasons used by the playback sources.
namespace playback_drop {
inline constexpr const char* kBadRow = "bad row";              // a field unparseable / out of range
inline constexpr const char* kOutOfOrder = "out of order";     // t earlier than the previous row
inline constexpr const char* kDuplicateTime = "duplicate time";  // same t (and same anchor for UWB)
inline constexpr const char* kMissingFrame = "missing frame";  // image file absent
inline constexpr const char* kBadFrame = "bad frame";          // image unreadable, truncated or corrupt
inline constexpr const char* kFrameSize = "frame size";        // image size differs from camera.yaml
inline constexpr const char* kOutOfRange = drop_reason::kOutOfRange;  // a value beyond the sensor's range
}  // namespace playback_drop

class CsvRowSource : public Source {
 public:
  std::string name() const override { return name_; }
  bool next(SensorData& out) override;
  // Rows handed out so far.
  std::uint64_t emitted() const { return emitted_; }
  const std::string& path() const { return reader_.path(); }
  // The sensor's plausible ranges (session.yaml `sensor_limits`; defaults otherwise).
  void set_limits(const SensorLimits& limits) { limits_ = limits; }

 protected:
  // Opens the file and reads its header; throws InputError when the file cannot be read
  // or lacks a column of `required` (checked here so open_playback fails early, exit 2).
  CsvRowSource(const std::string& path, std::string name, const std::vector<const char*>& required);

  // Parses the current row (time included); throws InputError for an unusable field.
  virtual SensorData parse_row(const CsvReader& row) = 0;
  // Rows sharing a time stamp are duplicates unless their keys differ (UWB: the anchor id).
  virtual long long duplicate_key(const SensorData&) const { return 0; }
  // Last step once the row passed the time checks (frames: load the image). Returns false
  // after counting the reason in drops() to skip the row.
  virtual bool complete(SensorData&) { return true; }

  // The next row that parsed and passed the time checks, before complete(); false at the
  // end of the file. next() is this followed by complete().
  bool next_checked_row(SensorData& out);
  // Counts a row handed out by an override of next().
  void count_emitted() { ++emitted_; }

  // Column of `name` (from the header read at construction).
  int col(const char* name) const { return reader_.column(name); }
  CsvReader reader_;

 private:
  SensorLimits limits_;
  std::string name_;
  std::optional<TimeNs> last_t_;
  std::vector<long long> keys_at_last_t_;
  std::uint64_t emitted_ = 0;
};

// Reads the `t` column of the current row (seconds) onto the ns timeline.
TimeNs row_time(const CsvReader& row, int t_col);

}  // namespace luxloc
