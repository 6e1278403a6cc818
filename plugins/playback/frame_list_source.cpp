#include "plugins/playback/frame_list_source.hpp"

#include <opencv2/imgcodecs.hpp>

#include "core/common/input_error.hpp"

namespace luxloc {

FrameListSource::FrameListSource(const std::string& path, std::filesystem::path base_dir,
                                 std::optional<cv::Size> expected_size)
    : CsvRowSource(path, "playback:frames", {"t", "file"}),
      base_dir_(std::move(base_dir)),
      expected_size_(expected_size),
      t_(col("t")),
      file_(col("file")) {}

SensorData FrameListSource::parse_row(const CsvReader& row) {
  FrameSample s;
  s.t = row_time(row, t_);
  s.file = std::string(row.field(file_));
  if (s.file.empty()) throw InputError(row.path(), row.line(), "file", "empty file name");
  line_ = row.line();
  return s;
}

bool FrameListSource::complete(SensorData& data) {
  FrameSample& s = std::get<FrameSample>(data);
  const std::filesystem::path p = base_dir_ / s.file;
  std::error_code ec;
  // Check first: imread() of a missing file logs an OpenCV warning per frame.
  if (std::filesystem::is_regular_file(p, ec)) {
    try {
      s.gray = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
    } catch (const cv::Exception&) {
      s.gray.release();
    }
  }
  if (s.gray.empty() || s.gray.type() != CV_8UC1) {
    drops().add(playback_drop::kMissingFrame,
                InputError(path(), line_, "file", "cannot read '" + s.file + "'").what());
    return false;
  }
  if (expected_size_ && s.gray.size() != *expected_size_) {
    drops().add(playback_drop::kFrameSize,
                InputError(path(), line_, "file",
                           "'" + s.file + "' is " + std::to_string(s.gray.cols) + "x" +
                               std::to_string(s.gray.rows) + ", the camera model says " +
                               std::to_string(expected_size_->width) + "x" +
                               std::to_string(expected_size_->height))
                    .what());
    return false;
  }
  s.file = p.string();
  return true;
}

}  // namespace luxloc
