#pragma once
// frames.csv playback (SPEC.md): t,file — t is the start of exposure of row 0, file is
// relative to the session folder (or absolute), PNG or JPG, gray or colour (converted to
// 8-bit gray; sensor orientation kept, EXIF rotation ignored, FIELD_NOTES "decode in sensor
// rows"). Images are decoded inside next(), i.e. on the source's own pipeline thread.
// A missing or unreadable image ("missing frame") or one whose size differs from the camera
// model ("frame size") is skipped and counted, never the end of the run.
#include <filesystem>
#include <optional>
#include <opencv2/core/types.hpp>

#include "plugins/playback/csv_row_source.hpp"

namespace luxloc {

class FrameListSource : public CsvRowSource {
 public:
  // `base_dir`: folder the file names are relative to. `expected_size`: camera.yaml's
  // image size when known (frames of another size are dropped).
  FrameListSource(const std::string& path, std::filesystem::path base_dir,
                  std::optional<cv::Size> expected_size = std::nullopt);

 protected:
  SensorData parse_row(const CsvReader& row) override;
  bool complete(SensorData& s) override;

 private:
  std::filesystem::path base_dir_;
  std::optional<cv::Size> expected_size_;
  int t_ = -1, file_ = -1;
  int line_ = 0;  // line of the row being completed (for messages)
};

}  // namespace luxloc
