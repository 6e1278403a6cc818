#include "plugins/output/status_line.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace luxloc {

StatusLine::StatusLine(std::vector<std::string> source_names, std::shared_ptr<const SampleCounters> counters,
                       double span_s, TimeNs t0, std::FILE* out)
    : names_(std::move(source_names)),
      counters_(std::move(counters)),
      span_s_(span_s),
      t0_(t0),
      out_(out),
      last_counts_(names_.size(), 0),
      rates_(names_.size(), 0.0) {}

std::string StatusLine::render(const PoseEstimate& p, double wall_s) {
  // Rates per source over the time since the last drawing (wall clock).
  const double dt = wall_s - last_wall_s_;
  if (dt > 0.05) {
    for (std::size_t i = 0; i < names_.size() && i < counters_->size(); ++i) {
      const std::uint64_t c = counters_->count(i);
      rates_[i] = static_cast<double>(c - last_counts_[i]) / dt;
      last_counts_[i] = c;
    }
    last_wall_s_ = wall_s;
  }
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  const double t = ns_to_seconds(p.t - t0_);
  if (span_s_ > 0) {
    const double f = std::clamp(t / span_s_, 0.0, 1.0);
    const int filled = static_cast<int>(std::lround(f * 20));
    s << "[" << std::string(static_cast<std::size_t>(filled), '#') << std::string(static_cast<std::size_t>(20 - filled), '.')
      << "] " << std::lround(100 * f) << "% ";
  }
  s << "t " << t << " s";
  for (std::size_t i = 0; i < names_.size(); ++i) s << " | " << names_[i] << " " << std::lround(rates_[i]) << "/s";
  s.precision(2);
  const double spread = std::sqrt((std::isfinite(p.sigma_x) ? p.sigma_x * p.sigma_x : 0.0) +
                                  (std::isfinite(p.sigma_y) ? p.sigma_y * p.sigma_y : 0.0));
  s << " | LEDs " << p.leds << " | x " << p.p_BinW.x() << " y " << p.p_BinW.y() << " | sigma " << spread << " m";
  if (!p.mode.empty()) s << " | " << p.mode;
  if (std::isfinite(p.latency_s)) latency_.add(p.latency_s);
  if (const LatencySummary l = latency_.summary(); l.count > 0)
    s << " | latency p50 " << 1e3 * l.p50_s << " p99 " << 1e3 * l.p99_s << " ms";
  return s.str();
}

void StatusLine::write(const PoseEstimate& pose) {
  const auto now = std::chrono::steady_clock::now();
  last_pose_ = pose;
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(250)) {
    if (std::isfinite(pose.latency_s)) latency_.add(pose.latency_s);
    pending_ = true;
    return;
  }
  pending_ = false;
  last_draw_ = now;
  const std::string line = render(pose, std::chrono::duration<double>(now - start_).count());
  // Pad over the previous, longer line; no newline until flush().
  std::fprintf(out_, "\r%s%s", line.c_str(),
               line.size() < last_len_ ? std::string(last_len_ - line.size(), ' ').c_str() : "");
  std::fflush(out_);
  last_len_ = line.size();
  drawn_ = true;
}

void StatusLine::flush() {
  if (!drawn_) return;
  if (pending_) {  // the final state, not the one of up to 250 ms before
    last_draw_ = {};
    drawn_ = false;
    write(last_pose_);
  }
  std::fputc('\n', out_);
  std::fflush(out_);
  drawn_ = false;
}

namespace {

// t of the first data row and of the last line of a CSV with a `t` column first or named.
bool csv_span(const std::filesystem::path& p, double& first, double& last) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::string header, row;
  while (std::getline(in, header) && (header.empty() || header[0] == '#')) {
  }
  std::size_t col = 0;
  {
    std::istringstream h(header);
    std::string name;
    bool found = false;
    for (std::size_t i = 0; std::getline(h, name, ','); ++i)
      if (name == "t") {
        col = i;
        found = true;
        break;
      }
    if (!found) return false;
  }
  const auto field = [col](const std::string& line, double& v) {
    std::istringstream l(line);
    std::string f;
    for (std::size_t i = 0; i <= col; ++i)
      if (!std::getline(l, f, ',')) return false;
    try {
      v = std::stod(f);
      return std::isfinite(v);
    } catch (const std::exception&) {
      return false;
    }
  };
  while (std::getline(in, row))
    if (!row.empty() && row[0] != '#' && field(row, first)) break;
  // The last complete line: read the file's tail.
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(std::max<std::streamoff>(0, size - 4096));
  std::string tail((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream lines(tail);
  bool any = false;
  while (std::getline(lines, row)) {
    double v;
    if (field(row, v)) {
      last = v;
      any = true;
    }
  }
  return any && last >= first;
}

}  // namespace

bool session_time_span(const std::string& dir, TimeNs& t_first, TimeNs& t_last) {
  bool any = false;
  for (const char* name : {"imu.csv", "frames.csv", "uwb.csv", "fixes.csv", "odom.csv"}) {
    double a = 0, b = 0;
    if (!csv_span(std::filesystem::path(dir) / name, a, b)) continue;
    const TimeNs ta = seconds_to_ns(a), tb = seconds_to_ns(b);
    if (!any || ta < t_first) t_first = ta;
    if (!any || tb > t_last) t_last = tb;
    any = true;
  }
  return any;
}

}  // namespace luxloc
