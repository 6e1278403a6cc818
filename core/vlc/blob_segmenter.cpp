#include "core/vlc/blob_segmenter.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>

namespace luxloc {

int BlobSegmenter::find(int i) {
  while (runs_[static_cast<std::size_t>(i)].parent != i) {
    auto& r = runs_[static_cast<std::size_t>(i)];
    r.parent = runs_[static_cast<std::size_t>(r.parent)].parent;  // path halving
    i = r.parent;
  }
  return i;
}

void BlobSegmenter::segment(const cv::Mat& gray8, double threshold, int gap_rows, int min_pixels) {
  runs_.clear();
  blobs_.clear();
  all_.clear();
  const int H = gray8.rows, W = gray8.cols;
  row_first_.assign(static_cast<std::size_t>(H + 1), 0);
  if (gray8.empty()) return;
  // 8-bit threshold (vectorised); then runs, skipping all-dark 8-byte words.
  cv::threshold(gray8, binary_, threshold, 255, cv::THRESH_BINARY);
  constexpr int kColTol = 2;  // the 3-wide dilation: runs 2 columns apart still touch
  gap_rows = std::max(1, gap_rows);
  for (int r = 0; r < H; ++r) {
    row_first_[static_cast<std::size_t>(r)] = static_cast<int>(runs_.size());
    const uchar* p = binary_.ptr<uchar>(r);
    int u = 0, start = -1;
    while (u < W) {
      if (start < 0 && u + 8 <= W) {
        std::uint64_t word;
        std::memcpy(&word, p + u, 8);
        if (word == 0) {
          u += 8;
          continue;
        }
      }
      if (p[u]) {
        if (start < 0) start = u;
      } else if (start >= 0) {
        runs_.push_back({r, start, u - 1, static_cast<int>(runs_.size())});
        start = -1;
      }
      ++u;
    }
    if (start >= 0) runs_.push_back({r, start, W - 1, static_cast<int>(runs_.size())});
  }
  row_first_[static_cast<std::size_t>(H)] = static_cast<int>(runs_.size());

  // Link each run with the runs of the previous gap_rows rows (and its own row) that
  // overlap it within the column tolerance.
  for (int j = 0; j < static_cast<int>(runs_.size()); ++j) {
    const Run rj = runs_[static_cast<std::size_t>(j)];
    const int from = row_first_[static_cast<std::size_t>(std::max(0, rj.row - gap_rows))];
    for (int i = from; i < j; ++i) {
      const Run& ri = runs_[static_cast<std::size_t>(i)];
      if (ri.u0 <= rj.u1 + kColTol && rj.u0 <= ri.u1 + kColTol) {
        const int a = find(i), b = find(j);
        if (a != b) runs_[static_cast<std::size_t>(std::max(a, b))].parent = std::min(a, b);
      }
    }
  }

  // Group statistics, in order of the groups' first run (deterministic).
  group_of_.resize(runs_.size());
  stats_index_.assign(runs_.size(), -1);
  for (int j = 0; j < static_cast<int>(runs_.size()); ++j) {
    const int g = find(j);
    group_of_[static_cast<std::size_t>(j)] = g;
    int& si = stats_index_[static_cast<std::size_t>(g)];
    const Run& rj = runs_[static_cast<std::size_t>(j)];
    if (si < 0) {
      si = static_cast<int>(all_.size());
      all_.push_back({rj.row, rj.row, rj.u0, rj.u1, 0, g});
    }
    BlobRegion& b = all_[static_cast<std::size_t>(si)];
    b.first_row = std::min(b.first_row, rj.row);
    b.last_row = std::max(b.last_row, rj.row);
    b.first_col = std::min(b.first_col, rj.u0);
    b.last_col = std::max(b.last_col, rj.u1);
    b.bright_pixels += rj.u1 - rj.u0 + 1;
  }
  for (const BlobRegion& b : all_)
    if (b.bright_pixels >= min_pixels) blobs_.push_back(b);
}

bool BlobSegmenter::mark_foreign(const BlobRegion& blob, const cv::Rect& roi, cv::Mat& mask) const {
  mask.release();
  if (roi.empty() || runs_.empty()) return false;
  const int r_end = std::min(roi.y + roi.height, static_cast<int>(row_first_.size()) - 1);
  for (int r = std::max(0, roi.y); r < r_end; ++r)
    for (int i = row_first_[static_cast<std::size_t>(r)]; i < row_first_[static_cast<std::size_t>(r + 1)]; ++i) {
      const Run& run = runs_[static_cast<std::size_t>(i)];
      if (group_of_[static_cast<std::size_t>(i)] == blob.group) continue;
      const int a = std::max(run.u0, roi.x), b = std::min(run.u1, roi.x + roi.width - 1);
      if (a > b) continue;
      if (mask.empty()) mask = cv::Mat::zeros(roi.height, roi.width, CV_8UC1);
      std::memset(mask.ptr<uchar>(r - roi.y) + (a - roi.x), 255, static_cast<std::size_t>(b - a + 1));
    }
  return !mask.empty();
}

}  // namespace luxloc
