#pragma once
// frames.csv playback (SPEC.md): t,file — t is the start of exposure of row 0, file is
// relative to the session folder (or absolute), PNG or JPG, gray or colour (converted to
// 8-bit gray; sensor orientation kept, EXIF rotation ignored, FIELD_NOTES "decode in sensor
// rows"). A missing image ("missing frame"), an unreadable, truncated or corrupt one ("bad
// frame", checked and decoded without the image libraries' stderr noise: image_file.hpp) or
// one whose size differs from the camera model ("frame size") is skipped and counted, never
// the end of the run.
//
// Image decoding (a noisy 640x480 PNG takes ~3 ms, far more than decoding its stripes) runs
// ahead of the consumer on up to `decode_threads` worker threads, a bounded window of
// frames in flight; samples still come out strictly in file order and the drop accounting
// happens on the source's own thread, in order, exactly as without read-ahead.
#include <deque>
#include <filesystem>
#include <future>
#include <optional>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "plugins/playback/csv_row_source.hpp"
#include "plugins/playback/image_file.hpp"

namespace luxloc {

class FrameListSource : public CsvRowSource {
 public:
  // `base_dir`: folder the file names are relative to. `expected_size`: camera.yaml's
  // image size when known (frames of another size are dropped). `decode_threads`: images
  // decoded ahead in parallel (0: one per hardware thread, at most 8; 1: no read-ahead).
  FrameListSource(const std::string& path, std::filesystem::path base_dir,
                  std::optional<cv::Size> expected_size = std::nullopt, int decode_threads = 0);
  ~FrameListSource() override;

  bool next(SensorData& out) override;

 protected:
  SensorData parse_row(const CsvReader& row) override;

 private:
  struct InFlight {
    FrameSample sample;  // gray still empty
    int line = 0;
    std::future<GrayImage> image;
  };
  bool accept(FrameSample& s, GrayImage image, int line);

  std::filesystem::path base_dir_;
  std::optional<cv::Size> expected_size_;
  std::size_t window_ = 1;
  std::deque<InFlight> in_flight_;
  int t_ = -1, file_ = -1;
};

}  // namespace luxloc
