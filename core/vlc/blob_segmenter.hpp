#pragma once
// Segmentation of a rolling-shutter frame into one region per LED (SEEDS.md A, S203:
// "segment the frame into single-LED regions"). Pixels above a threshold form row runs;
// runs are linked when they overlap (within 2 columns) across at most `gap_rows` rows, so
// the dark stripes inside one LED do not split it. This equals a connected-component
// labelling after a (3 x gap_rows) dilation, at a fraction of the cost: only the bright
// runs are touched, not a label image of the whole frame.
#include <opencv2/core/mat.hpp>
#include <vector>

namespace luxloc {

struct BlobRegion {
  int first_row = 0, last_row = -1, first_col = 0, last_col = -1;  // extent of the bright pixels
  int bright_pixels = 0;
  int group = -1;  // internal id of the run group
  cv::Rect box() const { return {first_col, first_row, last_col - first_col + 1, last_row - first_row + 1}; }
};

class BlobSegmenter {
 public:
  // Pixels > threshold (an 8-bit frame). Regions with fewer than min_pixels bright pixels
  // are dropped (noise). Buffers are reused between calls.
  void segment(const cv::Mat& gray8, double threshold, int gap_rows, int min_pixels);

  const std::vector<BlobRegion>& blobs() const { return blobs_; }

  // Marks with 255, in `mask` (CV_8UC1 of roi's size, zeroed here), the bright pixels
  // inside `roi` that belong to any other run group than `blob`'s. Returns false (and
  // leaves `mask` empty) when there are none, the common case.
  bool mark_foreign(const BlobRegion& blob, const cv::Rect& roi, cv::Mat& mask) const;

 private:
  struct Run {
    int row, u0, u1, parent;
  };
  int find(int i);

  cv::Mat binary_;
  std::vector<Run> runs_;
  std::vector<int> row_first_;  // index of the first run of each row (size rows + 1)
  std::vector<int> group_of_;   // run -> root run
  std::vector<int> stats_index_;
  std::vector<BlobRegion> all_;
  std::vector<BlobRegion> blobs_;
};

}  // namespace luxloc
