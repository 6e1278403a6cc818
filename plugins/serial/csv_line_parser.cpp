#include "plugins/serial/csv_line_parser.hpp"

#include "plugins/serial/text_fields.hpp"

#include <numbers>
#include <cmath>
#include <stdexcept>

namespace luxloc {
namespace {

constexpr const char* kNames[10] = {"t", "ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz"};

int name_index(std::string_view n) {
  for (int k = 0; k < 10; ++k)
    if (n == kNames[k]) return k;
  return -1;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> f;
  const bool delimited = line.find_first_of(",;") != std::string_view::npos;
  std::size_t i = 0;
  if (delimited) {
    f = split_trimmed(line, ",;");
  } else {
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      f.push_back(line.substr(i, j - i));
      i = j;
    }
  }
  return f;
}

}  // namespace

double CsvLineOptions::acc_unit(const std::string& n) {
  if (n == "mps2" || n == "m/s2" || n == "m/s^2") return 1.0;
  if (n == "g") return 9.80665;
  throw std::invalid_argument("acc_unit '" + n + "' (valid: mps2, g)");
}
double CsvLineOptions::gyro_unit(const std::string& n) {
  if (n == "rps" || n == "rad/s") return 1.0;
  if (n == "dps" || n == "deg/s") return std::numbers::pi / 180.0;
  throw std::invalid_argument("gyro_unit '" + n + "' (valid: rps, dps)");
}
double CsvLineOptions::mag_unit(const std::string& n) {
  if (n == "ut" || n == "uT") return 1.0;
  if (n == "gauss") return 100.0;
  if (n == "mgauss") return 0.1;
  if (n == "nt" || n == "nT") return 1e-3;
  throw std::invalid_argument("mag_unit '" + n + "' (valid: ut, gauss, mgauss, nt)");
}
double CsvLineOptions::time_unit(const std::string& n) {
  if (n == "s") return 1.0;
  if (n == "ms") return 1e-3;
  if (n == "us") return 1e-6;
  throw std::invalid_argument("time_unit '" + n + "' (valid: s, ms, us)");
}

std::vector<std::string> CsvLineOptions::parse_columns(const std::string& text) {
  std::vector<std::string> cols;
  std::size_t i = 0;
  while (true) {
    const std::size_t j = text.find(':', i);
    cols.push_back(text.substr(i, j == std::string::npos ? std::string::npos : j - i));
    if (j == std::string::npos) break;
    i = j + 1;
  }
  bool seen[10] = {};
  for (const std::string& c : cols) {
    if (c == "_") continue;
    const int k = name_index(c);
    if (k < 0) throw std::invalid_argument("columns '" + text + "': unknown column '" + c + "' (t, ax..gz, mx..mz, _)");
    if (seen[k]) throw std::invalid_argument("columns '" + text + "': '" + c + "' appears twice");
    seen[k] = true;
  }
  for (int k = 1; k <= 6; ++k)
    if (!seen[k]) throw std::invalid_argument("columns '" + text + "': missing '" + kNames[k] + "'");
  if ((seen[7] + seen[8] + seen[9]) % 3 != 0)
    throw std::invalid_argument("columns '" + text + "': give all of mx, my, mz or none");
  return cols;
}

CsvLineParser::CsvLineParser(DropCounts& drops, const CsvLineOptions& options)
    : ImuStreamParser(drops), options_(options) {
  set_columns(options.columns.empty() ? std::vector<std::string>(kNames, kNames + 10) : options.columns);
}

void CsvLineParser::set_columns(const std::vector<std::string>& names) {
  columns_ = names;
  for (int& c : col_) c = -1;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const int k = name_index(names[i]);
    if (k >= 0) col_[k] = static_cast<int>(i);
  }
}

void CsvLineParser::reset() {
  line_.clear();
  discarding_ = false;
  have_offset_ = false;
}

void CsvLineParser::feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
                         std::vector<ImuSample>& out) {
  for (std::size_t k = 0; k < size; ++k) {
    const char c = static_cast<char>(data[k]);
    if (c == '\n') {
      if (!discarding_) {
        const TimeNs t = t_end - static_cast<TimeNs>(std::llround(static_cast<double>(size - 1 - k) * byte_ns));
        on_line(line_, t, out);
      }
      line_.clear();
      discarding_ = false;
      continue;
    }
    if (discarding_) continue;
    if (line_.size() >= options_.max_line) {
      drops_.add(serial_drop::kLongLine, "a line longer than " + std::to_string(options_.max_line) + " bytes");
      line_.clear();
      discarding_ = true;
      continue;
    }
    line_.push_back(c);
  }
}

void CsvLineParser::on_line(std::string_view line, TimeNs t_arrival, std::vector<ImuSample>& out) {
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  while (!line.empty() && (line.front() == ' ' || line.front() == '\t' || line.front() == '\0')) line.remove_prefix(1);
  if (line.empty() || line.front() == '#') return;
  ++lines_;
  const std::vector<std::string_view> f = split(line);
  double first = 0.0;
  if (!parse_finite_number(f[0], first)) {
    // A header of known names sets the order unless one was configured.
    bool header = true;
    for (std::string_view n : f) header = header && (n == "_" || name_index(n) >= 0);
    if (header) {
      if (options_.columns.empty()) set_columns(std::vector<std::string>(f.begin(), f.end()));
      return;
    }
  }
  auto field = [&](int k, double& v) -> bool {
    const int c = col_[k];
    return c >= 0 && c < static_cast<int>(f.size()) && parse_finite_number(f[c], v);
  };
  ImuSample s;
  double v[10] = {};
  bool ok = true;
  for (int k = 1; k <= 6; ++k) ok = ok && field(k, v[k]);
  if (ok && options_.device_time) ok = field(0, v[0]);
  // A device time beyond +/-4e9 s (year 2096 as a Unix time) is no clock; it would also
  // overflow the ns offsets below (found by fuzz_csv_imu_line: t = 1e300).
  constexpr double kMaxDeviceTimeS = 4.0e9;
  if (ok && options_.device_time && !(std::abs(v[0] * options_.time_to_s) <= kMaxDeviceTimeS)) ok = false;
  if (!ok) {
    drops_.add(serial_drop::kBadLine, "unusable line: '" + std::string(line.substr(0, 80)) + "'");
    return;
  }
  s.acc_inB = Eigen::Vector3d(v[1], v[2], v[3]) * options_.acc_to_mps2;
  s.gyro_inB = Eigen::Vector3d(v[4], v[5], v[6]) * options_.gyro_to_rps;
  if (field(7, v[7]) && field(8, v[8]) && field(9, v[9])) {
    s.mag_inB = Eigen::Vector3d(v[7], v[8], v[9]) * options_.mag_to_ut;
    s.has_mag = true;
  }
  s.t = t_arrival;
  if (options_.device_time) {
    const TimeNs t_dev = seconds_to_ns(v[0] * options_.time_to_s);
    const TimeNs offset = t_arrival - t_dev;
    // The least-delayed line defines the offset; a device clock that jumped (reset) or
    // drifted a second behind re-anchors it.
    if (!have_offset_ || offset < offset_ || offset - offset_ > kNsPerSecond) offset_ = offset;
    have_offset_ = true;
    s.t = t_dev + offset_;
  }
  out.push_back(s);
}

}  // namespace luxloc
