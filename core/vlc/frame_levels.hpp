#pragma once
// Background and noise of a short-exposure frame, and the threshold above which a pixel is
// lit by an LED: a quantile of a sub-sampled histogram (the median by default: robust to
// the few LED pixels) and the 1-sigma spread above it (the quantile 34.13 points higher
// minus it: robust to a black level clipped at 0). A frame mostly filled by the light (row
// time calibration) takes a low quantile: its dark stripes are the background.
#include <opencv2/core/mat.hpp>

namespace luxloc {

// The 8-bit gray image of a camera frame: `in` itself when CV_8UC1, else CV_8UC3 (BGR),
// CV_8UC4 (BGRA) or CV_16UC1 (top 8 bits) converted into `buffer`; nullptr for other types.
const cv::Mat* as_gray8(const cv::Mat& in, cv::Mat& buffer);

struct FrameLevels {
  double background = 0.0, noise = 1.0, threshold = 16.0;
};

// `gray8`: CV_8UC1. threshold = background + max(min_contrast_dn, threshold_sigma * noise).
FrameLevels frame_levels(const cv::Mat& gray8, double min_contrast_dn, double threshold_sigma,
                         double background_quantile = 0.5);

}  // namespace luxloc
