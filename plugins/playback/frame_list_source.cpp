#include "plugins/playback/frame_list_source.hpp"

#include <algorithm>
#include <thread>

#include "core/common/input_error.hpp"

namespace luxloc {
FrameListSource::FrameListSource(const std::string& path, std::filesystem::path base_dir,
                                 std::optional<cv::Size> expected_size, int decode_threads)
    : CsvRowSource(path, "playback:frames", {"t", "file"}),
      base_dir_(std::move(base_dir)),
      expected_size_(expected_size),
      t_(col("t")),
      file_(col("file")) {
  if (decode_threads <= 0)
    decode_threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 8);
  window_ = static_cast<std::size_t>(decode_threads);
}

FrameListSource::~FrameListSource() {
  // std::async futures join in their destructors: nothing outlives the source.
  in_flight_.clear();
}

SensorData FrameListSource::parse_row(const CsvReader& row) {
  FrameSample s;
  s.t = row_time(row, t_);
  s.file = std::string(row.field(file_));
  if (s.file.empty()) throw InputError(row.path(), row.line(), "file", "empty file name");
  return s;
}

bool FrameListSource::next(SensorData& out) {
  for (;;) {
    // Keep the window full: rows are parsed and time-checked here, in order; only the
    // image decoding goes to the workers.
    SensorData row;
    while (in_flight_.size() < window_ && next_checked_row(row)) {
      InFlight f;
      f.sample = std::get<FrameSample>(std::move(row));
      f.line = reader_.line();
      const std::filesystem::path p = base_dir_ / f.sample.file;
      f.image = window_ > 1 ? std::async(std::launch::async, read_gray_image, p)
                            : std::async(std::launch::deferred, read_gray_image, p);
      in_flight_.push_back(std::move(f));
    }
    if (in_flight_.empty()) return false;
    InFlight f = std::move(in_flight_.front());
    in_flight_.pop_front();
    if (!accept(f.sample, f.image.get(), f.line)) continue;
    out = std::move(f.sample);
    count_emitted();
    return true;
  }
}

bool FrameListSource::accept(FrameSample& s, GrayImage decoded, int line) {
  if (decoded.gray.empty()) {
    const bool absent = decoded.error == "file not found";
    drops().add(absent ? playback_drop::kMissingFrame : playback_drop::kBadFrame,
                InputError(path(), line, "file", "cannot read '" + s.file + "': " + decoded.error).what());
    return false;
  }
  cv::Mat image = std::move(decoded.gray);
  if (expected_size_ && image.size() != *expected_size_) {
    drops().add(playback_drop::kFrameSize,
                InputError(path(), line, "file",
                           "'" + s.file + "' is " + std::to_string(image.cols) + "x" +
                               std::to_string(image.rows) + ", the camera model says " +
                               std::to_string(expected_size_->width) + "x" +
                               std::to_string(expected_size_->height))
                    .what());
    return false;
  }
  s.gray = std::move(image);
  s.file = (base_dir_ / s.file).string();
  return true;
}

}  // namespace luxloc
