#include "core/eval/trajectory_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrid(225, 225, 225), kAxis(60, 60, 60);
const cv::Scalar kTruth(40, 40, 40), kEstimate(200, 90, 20), kError(30, 30, 210), kRmse(0, 150, 0);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// A "nice" tick step (1, 2 or 5 x 10^k) giving about `target` ticks over `range`.
double nice_step(double range, int target) {
  if (!(range > 0.0) || !std::isfinite(range)) return 1.0;
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

std::string tick_label(double v, double step) {
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 6);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.45, const cv::Scalar& c = kBlack,
          int thickness = 1) {
  cv::putText(img, s, at, kFont, scale, c, thickness, cv::LINE_AA);
}

int text_width(const std::string& s, double scale = 0.45) {
  int base = 0;
  return cv::getTextSize(s, kFont, scale, 1, &base).width;
}

void dashed_line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& c) {
  const double len = cv::norm(b - a);
  const int n = std::max(1, static_cast<int>(len / 8.0));
  for (int i = 0; i < n; i += 2)
    cv::line(img, a + (b - a) * (static_cast<double>(i) / n), a + (b - a) * (static_cast<double>(i + 1) / n), c, 1,
             cv::LINE_AA);
}

// Linear map from data coordinates to a pixel rectangle (y up).
struct Axes {
  cv::Rect box;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  cv::Point2d px(double x, double y) const {
    return {box.x + (x - x0) / (x1 - x0) * box.width, box.y + box.height - (y - y0) / (y1 - y0) * box.height};
  }
  // Frame, grid, tick labels and axis names.
  void draw(cv::Mat& img, double x_step, double y_step, const std::string& x_name, const std::string& y_name) const {
    for (double x = std::ceil(x0 / x_step) * x_step; x <= x1 + 1e-9 * x_step; x += x_step) {
      const int u = static_cast<int>(std::lround(px(x, y0).x));
      cv::line(img, {u, box.y}, {u, box.y + box.height}, kGrid, 1);
      cv::line(img, {u, box.y + box.height}, {u, box.y + box.height + 5}, kAxis, 1);
      const std::string l = tick_label(x, x_step);
      text(img, l, {u - text_width(l) / 2, box.y + box.height + 20});
    }
    for (double y = std::ceil(y0 / y_step) * y_step; y <= y1 + 1e-9 * y_step; y += y_step) {
      const int v = static_cast<int>(std::lround(px(x0, y).y));
      cv::line(img, {box.x, v}, {box.x + box.width, v}, kGrid, 1);
      cv::line(img, {box.x - 5, v}, {box.x, v}, kAxis, 1);
      const std::string l = tick_label(y, y_step);
      text(img, l, {box.x - 9 - text_width(l), v + 5});
    }
    cv::rectangle(img, box, kAxis, 1);
    text(img, x_name, {box.x + box.width / 2 - text_width(x_name, 0.5) / 2, box.y + box.height + 40}, 0.5);
    // Vertical label drawn horizontally above the axis (Hershey fonts do not rotate).
    text(img, y_name, {box.x - 60, box.y - 10}, 0.5);
  }
};

void legend_entry(cv::Mat& img, cv::Point at, const cv::Scalar& c, const std::string& label, bool dashed = false) {
  if (dashed)
    dashed_line(img, at, at + cv::Point(30, 0), c);
  else
    cv::line(img, at, at + cv::Point(30, 0), c, 2, cv::LINE_AA);
  text(img, label, at + cv::Point(38, 5), 0.5);
}

void draw_xy_panel(cv::Mat& img, cv::Rect box, const std::vector<TruthRow>& truth, const EvalResult& r,
                   double gap_s) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  auto extend = [&](double x, double y) {
    xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  };
  for (const TruthRow& t : truth) extend(t.p_inW.x(), t.p_inW.y());
  for (const PoseError& e : r.errors) extend(e.p_est.x(), e.p_est.y());
  // Equal scale on both axes, with a margin, and at least 1 m shown.
  const double cx = 0.5 * (xmin + xmax), cy = 0.5 * (ymin + ymax);
  const double half_w = std::max(0.5, 0.55 * (xmax - xmin)), half_h = std::max(0.5, 0.55 * (ymax - ymin));
  const double scale = std::min(box.width / (2 * half_w), box.height / (2 * half_h));  // px per m
  Axes ax;
  ax.box = box;
  ax.x0 = cx - box.width / (2 * scale), ax.x1 = cx + box.width / (2 * scale);
  ax.y0 = cy - box.height / (2 * scale), ax.y1 = cy + box.height / (2 * scale);
  const double step = nice_step(std::max(ax.x1 - ax.x0, ax.y1 - ax.y0), 10);
  ax.draw(img, step, step, "x (m, east)", "y (m, north)");

  cv::Mat roi = img(box);
  const cv::Point2d off(box.x, box.y);
  std::vector<cv::Point> line;
  for (const TruthRow& t : truth) line.push_back(ax.px(t.p_inW.x(), t.p_inW.y()) - off);
  cv::polylines(roi, line, false, kTruth, 2, cv::LINE_AA);
  line.clear();
  auto flush = [&] {
    if (line.size() >= 2) cv::polylines(roi, line, false, kEstimate, 1, cv::LINE_AA);
    if (line.size() == 1) cv::circle(roi, line.front(), 2, kEstimate, cv::FILLED, cv::LINE_AA);
    line.clear();
  };
  for (std::size_t i = 0; i < r.errors.size(); ++i) {
    if (i > 0 && ns_to_seconds(r.errors[i].t - r.errors[i - 1].t) > gap_s) flush();
    line.push_back(ax.px(r.errors[i].p_est.x(), r.errors[i].p_est.y()) - off);
  }
  flush();
  if (!truth.empty()) {
    const cv::Point2d s = ax.px(truth.front().p_inW.x(), truth.front().p_inW.y());
    cv::circle(img, s, 6, kTruth, 2, cv::LINE_AA);
  }
  // Legend, top-right inside the panel.
  const cv::Rect lg(box.x + box.width - 190, box.y + 10, 180, 80);
  cv::rectangle(img, lg, kWhite, cv::FILLED);
  cv::rectangle(img, lg, kAxis, 1);
  legend_entry(img, {lg.x + 10, lg.y + 20}, kTruth, "truth");
  legend_entry(img, {lg.x + 10, lg.y + 42}, kEstimate, "estimate");
  cv::circle(img, cv::Point(lg.x + 25, lg.y + 64), 6, kTruth, 2, cv::LINE_AA);
  text(img, "start", {lg.x + 48, lg.y + 69}, 0.5);
  // Scale bar: one tick step.
  const int bar = static_cast<int>(std::lround(step * scale));
  const cv::Point b0(box.x + 15, box.y + box.height - 15);
  cv::line(img, b0, b0 + cv::Point(bar, 0), kBlack, 2);
  text(img, tick_label(step, step) + " m", b0 + cv::Point(bar + 8, 5));
}

void draw_error_panel(cv::Mat& img, cv::Rect box, const EvalResult& r, double gap_s) {
  Axes ax;
  ax.box = box;
  ax.x0 = 0.0;
  ax.x1 = std::max(1e-3, ns_to_seconds(r.truth_t1 - r.truth_t0));
  ax.y0 = 0.0;
  ax.y1 = std::max(0.01, (r.n ? r.max_m : 0.0) * 1.1);
  ax.draw(img, nice_step(ax.x1, 12), nice_step(ax.y1, 5), "time since the first truth row (s)",
          "horizontal error (m)");
  cv::Mat roi = img(box);
  const cv::Point2d off(box.x, box.y);
  std::vector<cv::Point> line;
  auto flush = [&] {
    if (line.size() >= 2) cv::polylines(roi, line, false, kError, 1, cv::LINE_AA);
    if (line.size() == 1) cv::circle(roi, line.front(), 2, kError, cv::FILLED, cv::LINE_AA);
    line.clear();
  };
  for (std::size_t i = 0; i < r.errors.size(); ++i) {
    if (i > 0 && ns_to_seconds(r.errors[i].t - r.errors[i - 1].t) > gap_s) flush();
    line.push_back(ax.px(ns_to_seconds(r.errors[i].t - r.truth_t0), r.errors[i].err_m) - off);
  }
  flush();
  if (r.n > 0) {
    dashed_line(img, ax.px(ax.x0, r.rmse_m), ax.px(ax.x1, r.rmse_m), kRmse);
    legend_entry(img, {box.x + box.width - 330, box.y - 12}, kError, "error");
    char buf[64];
    std::snprintf(buf, sizeof buf, "RMSE %.3f m", r.rmse_m);
    legend_entry(img, {box.x + box.width - 200, box.y - 12}, kRmse, buf, true);
  }
}

}  // namespace

cv::Mat draw_trajectory_plot(const std::vector<TruthRow>& truth, const EvalResult& r, const PlotOptions& o) {
  const int w = std::max(400, o.width), h = std::max(400, o.height);
  cv::Mat img(h, w, CV_8UC3, kWhite);
  char buf[200];
  if (r.n > 0)
    std::snprintf(buf, sizeof buf, "ATE RMSE %.3f m | median %.3f | p95 %.3f | max %.3f | n %zu | coverage %.1f %%",
                  r.rmse_m, r.median_m, r.p95_m, r.max_m, r.n, 100.0 * r.coverage);
  else
    std::snprintf(buf, sizeof buf, "no pose inside the truth span");
  text(img, o.title, {20, 28}, 0.7, kBlack, 2);
  text(img, buf, {20 + text_width(o.title, 0.7) + 30, 28}, 0.55);
  // Layout: XY panel ~2/3 of the height, error panel below.
  const int left = 90, right = 30;
  const int xy_top = 70, xy_h = static_cast<int>(0.60 * h);
  const int err_top = xy_top + xy_h + 90, err_h = h - err_top - 55;
  draw_xy_panel(img, cv::Rect(left, xy_top, w - left - right, xy_h), truth, r, o.gap_s);
  draw_error_panel(img, cv::Rect(left, err_top, w - left - right, std::max(50, err_h)), r, o.gap_s);
  return img;
}

void write_trajectory_plot(const std::string& png_path, const std::vector<TruthRow>& truth, const EvalResult& result,
                           const PlotOptions& options) {
  const cv::Mat img = draw_trajectory_plot(truth, result, options);
  bool ok = false;
  try {
    ok = cv::imwrite(png_path, img);
  } catch (const cv::Exception& e) {
    throw InputError(png_path, 0, "", std::string("cannot write the plot: ") + e.err);
  }
  if (!ok) throw InputError(png_path, 0, "", "cannot write the plot (PNG)");
}

}  // namespace luxloc
