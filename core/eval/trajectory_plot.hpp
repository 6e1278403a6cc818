#pragma once
// `luxloc eval --plot`: a PNG drawn with OpenCV only. Top panel: XY plot of the truth and
// the estimate (equal scale, axes in metres, grid, legend, start marker). Bottom panel:
// horizontal error (m) over time with the RMSE as a dashed line.
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "core/eval/trajectory_metrics.hpp"

namespace luxloc {

struct PlotOptions {
  int width = 1200;
  int height = 900;
  std::string title = "luxloc eval";
  double gap_s = 1.0;  // the estimate's line is broken across pose gaps longer than this
};

// BGR image of options.width x options.height.
cv::Mat draw_trajectory_plot(const std::vector<TruthRow>& truth, const EvalResult& result,
                             const PlotOptions& options = {});
// Draws and writes a PNG; throws InputError (the path) when it cannot be written.
void write_trajectory_plot(const std::string& png_path, const std::vector<TruthRow>& truth,
                           const EvalResult& result, const PlotOptions& options = {});

}  // namespace luxloc
