#include "core/eval/trajectory_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace luxloc {
namespace {

constexpr std::size_t kMaxPoints = 4000;  // per polyline: the page stays small for long runs

std::string html_escape(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string num(double v, int decimals = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// Maps a data box onto an SVG box (y up).
struct Frame {
  double x0, y0, x1, y1;  // data
  double w, h, pad = 30;  // pixels
  double sx() const { return (w - 2 * pad) / std::max(1e-9, x1 - x0); }
  double sy() const { return (h - 2 * pad) / std::max(1e-9, y1 - y0); }
  double X(double x) const { return pad + (x - x0) * sx(); }
  double Y(double y) const { return h - pad - (y - y0) * sy(); }
};

template <typename Get>
std::string polyline(std::size_t n, const Frame& f, Get get, const char* cls) {
  std::string pts;
  const std::size_t step = std::max<std::size_t>(1, n / kMaxPoints);
  for (std::size_t i = 0; i < n; i += step) {
    const auto [x, y] = get(i);
    pts += num(f.X(x), 1) + "," + num(f.Y(y), 1) + " ";
  }
  return "<polyline class=\"" + std::string(cls) + "\" points=\"" + pts + "\"/>\n";
}

std::string axes(const Frame& f, const std::string& xlabel, const std::string& ylabel) {
  std::ostringstream s;
  s << "<rect class=\"axes\" x=\"" << f.pad << "\" y=\"" << f.pad << "\" width=\"" << f.w - 2 * f.pad << "\" height=\""
    << f.h - 2 * f.pad << "\"/>\n";
  s << "<text x=\"" << f.pad << "\" y=\"" << f.h - 8 << "\">" << num(f.x0, 1) << "</text>";
  s << "<text x=\"" << f.w - f.pad << "\" y=\"" << f.h - 8 << "\" text-anchor=\"end\">" << num(f.x1, 1) << " "
    << xlabel << "</text>";
  s << "<text x=\"4\" y=\"" << f.pad - 8 << "\">" << ylabel << " (" << num(f.y0, 2) << " .. " << num(f.y1, 2)
    << ")</text>\n";
  return s.str();
}

}  // namespace

std::string trajectory_report_html(const std::vector<TruthRow>& truth, const EvalResult& r, const std::string& title) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << html_escape(title)
    << "</title>\n<style>body{font:14px system-ui,sans-serif;background:#111;color:#ddd;margin:16px}"
       "svg{background:#1b1b1b;margin:8px 8px 0 0}text{fill:#999;font-size:11px}.axes{fill:none;stroke:#333}"
       ".truth{fill:none;stroke:#6c6;stroke-width:1.5}.est{fill:none;stroke:#39f;stroke-width:1.5}"
       ".err{fill:none;stroke:#f66;stroke-width:1}.bar{fill:#39f}td{padding:2px 8px}</style></head><body>\n";
  o << "<h1>" << html_escape(title) << "</h1>\n<table id=\"summary\">";
  const auto row = [&o](const char* k, const std::string& v) { o << "<tr><td>" << k << "</td><td>" << v << "</td></tr>"; };
  row("poses evaluated", std::to_string(r.n));
  row("ATE RMSE", num(r.rmse_m, 3) + " m");
  row("median", num(r.median_m, 3) + " m");
  row("p95", num(r.p95_m, 3) + " m");
  row("max", num(r.max_m, 3) + " m at t " + num(ns_to_seconds(r.t_max), 2) + " s");
  row("coverage", num(100 * r.coverage, 1) + " %");
  if (r.n_yaw) row("yaw RMSE", num(r.yaw_rmse_rad * 180 / M_PI, 2) + " deg");
  o << "</table>\n";

  // Trajectory: truth (green) and estimate (blue), same metric scale on both axes.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& t : truth) {
    x0 = std::min(x0, t.p_inW.x()); x1 = std::max(x1, t.p_inW.x());
    y0 = std::min(y0, t.p_inW.y()); y1 = std::max(y1, t.p_inW.y());
  }
  for (const auto& e : r.errors) {
    x0 = std::min(x0, e.p_est.x()); x1 = std::max(x1, e.p_est.x());
    y0 = std::min(y0, e.p_est.y()); y1 = std::max(y1, e.p_est.y());
  }
  const double span = std::max({x1 - x0, y1 - y0, 1.0});
  Frame map{x0 - 0.5, y0 - 0.5, x0 - 0.5 + span + 1, y0 - 0.5 + span + 1, 520, 520};
  o << "<svg id=\"trajectory\" width=\"520\" height=\"520\">\n" << axes(map, "m (x)", "y, m");
  o << polyline(truth.size(), map, [&](std::size_t i) { return std::pair{truth[i].p_inW.x(), truth[i].p_inW.y()}; }, "truth");
  o << polyline(r.errors.size(), map, [&](std::size_t i) { return std::pair{r.errors[i].p_est.x(), r.errors[i].p_est.y()}; },
                "est");
  o << "<text x=\"40\" y=\"50\" style=\"fill:#6c6\">truth</text><text x=\"90\" y=\"50\" style=\"fill:#39f\">estimate</text>"
       "</svg>\n";

  if (!r.errors.empty()) {
    // Error over time.
    const double t0 = ns_to_seconds(r.errors.front().t), t1 = ns_to_seconds(r.errors.back().t);
    Frame et{0.0, 0.0, std::max(1e-3, t1 - t0), std::max(r.max_m, 1e-3), 640, 250};
    o << "<svg id=\"error-over-time\" width=\"640\" height=\"250\">\n" << axes(et, "s", "error, m");
    o << polyline(r.errors.size(), et, [&](std::size_t i) {
      return std::pair{ns_to_seconds(r.errors[i].t) - t0, r.errors[i].err_m};
    }, "err");
    o << "</svg>\n";
    // Histogram: 30 bins up to the max.
    constexpr int kBins = 30;
    std::vector<std::size_t> bins(kBins, 0);
    const double width = std::max(r.max_m, 1e-6) / kBins;
    for (const auto& e : r.errors) ++bins[std::min<std::size_t>(kBins - 1, static_cast<std::size_t>(e.err_m / width))];
    const std::size_t most = *std::max_element(bins.begin(), bins.end());
    Frame hf{0.0, 0.0, width * kBins, static_cast<double>(most), 640, 250};
    o << "<svg id=\"error-histogram\" width=\"640\" height=\"250\">\n" << axes(hf, "m", "poses per bin");
    for (int b = 0; b < kBins; ++b) {
      const double x = hf.X(b * width), y = hf.Y(static_cast<double>(bins[static_cast<std::size_t>(b)]));
      o << "<rect class=\"bar\" x=\"" << num(x, 1) << "\" y=\"" << num(y, 1) << "\" width=\"" << num(width * hf.sx() - 1, 1)
        << "\" height=\"" << num(hf.Y(0) - y, 1) << "\"/>";
    }
    o << "\n</svg>\n";
  }
  o << "</body></html>\n";
  return o.str();
}

}  // namespace luxloc
