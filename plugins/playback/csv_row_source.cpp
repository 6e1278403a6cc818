#include "plugins/playback/csv_row_source.hpp"

#include <algorithm>
#include <cmath>

#include "core/common/input_error.hpp"

namespace luxloc {

TimeNs row_time(const CsvReader& row, int t_col) {
  const double t = row.number(t_col);
  // |t| beyond ~292 years of ns would overflow the int64 timeline.
  if (std::abs(t) > 9.0e9)
    throw InputError(row.path(), row.line(), "t", "time out of range: " + std::string(row.field(t_col)));
  return seconds_to_ns(t);
}

CsvRowSource::CsvRowSource(const std::string& path, std::string name, const std::vector<const char*>& required)
    : reader_(path), name_(std::move(name)) {
  for (const char* c : required) reader_.require_column(c);
}

bool CsvRowSource::next(SensorData& out) {
  SensorData s;
  while (next_checked_row(s)) {
    if (!complete(s)) continue;
    out = std::move(s);
    ++emitted_;
    return true;
  }
  return false;
}

bool CsvRowSource::next_checked_row(SensorData& out) {
  while (reader_.next_row()) {
    SensorData s;
    try {
      s = parse_row(reader_);
    } catch (const InputError& e) {
      drops().add(playback_drop::kBadRow, e.what());
      continue;
    }
    if (const auto bad = check_plausible(s, limits_)) {
      drops().add(playback_drop::kOutOfRange, InputError(reader_.path(), reader_.line(), bad->field, bad->what).what());
      continue;
    }
    const TimeNs t = sample_time(s);
    const long long key = duplicate_key(s);
    if (last_t_ && t < *last_t_) {
      drops().add(playback_drop::kOutOfOrder,
                  InputError(reader_.path(), reader_.line(), "t",
                             "time goes backwards (" + std::string(reader_.field(reader_.column("t"))) +
                                 " s after " + std::to_string(ns_to_seconds(*last_t_)) + " s)")
                      .what());
      continue;
    }
    if (last_t_ && t == *last_t_) {
      if (std::find(keys_at_last_t_.begin(), keys_at_last_t_.end(), key) != keys_at_last_t_.end()) {
        drops().add(playback_drop::kDuplicateTime,
                    InputError(reader_.path(), reader_.line(), "t",
                               "duplicated time stamp " + std::string(reader_.field(reader_.column("t"))))
                        .what());
        continue;
      }
      keys_at_last_t_.push_back(key);
    } else {
      last_t_ = t;
      keys_at_last_t_.assign(1, key);
    }
    out = std::move(s);
    return true;
  }
  return false;
}

}  // namespace luxloc
