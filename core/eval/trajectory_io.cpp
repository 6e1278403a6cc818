#include "core/eval/trajectory_io.hpp"

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool parse_double(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
}

TimeNs checked_time(const std::string& path, int line, double t) {
  if (!std::isfinite(t) || std::abs(t) > 9.0e9) throw InputError(path, line, "t", "time out of range");
  return seconds_to_ns(t);
}

// Rows of a CSV trajectory (t,x,y[,z,yaw]).
std::vector<TrajectoryPoint> read_csv_trajectory(CsvReader& r, bool strictly_increasing) {
  const int ct = r.require_column("t"), cx = r.require_column("x"), cy = r.require_column("y");
  const int cz = r.column("z"), cyaw = r.column("yaw");
  const int csx = r.column("sigma_x"), csy = r.column("sigma_y"), csyaw = r.column("sigma_yaw"),
            csz = r.column("sigma_z");
  std::vector<TrajectoryPoint> out;
  while (r.next_row()) {
    TrajectoryPoint p;
    p.t = checked_time(r.path(), r.line(), r.number(ct));
    p.p_inW = {r.number(cx), r.number(cy), r.number_or(cz, 0.0)};
    p.yaw = r.number_or(cyaw, kNaN);
    p.sigma_x = r.number_or(csx, kNaN);
    p.sigma_y = r.number_or(csy, kNaN);
    p.sigma_yaw = r.number_or(csyaw, kNaN);
    p.sigma_z = r.number_or(csz, kNaN);
    if (strictly_increasing && !out.empty() && p.t <= out.back().t)
      throw InputError(r.path(), r.line(), "t",
                       p.t == out.back().t ? "duplicated time stamp" : "time goes backwards (rows must be in time order)");
    out.push_back(p);
  }
  return out;
}

// yaw of R_BtoW = Rz(yaw) Ry(pitch) Rx(roll) from a unit quaternion.
double yaw_of(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

std::vector<PoseRow> read_tum(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  static const char* names[8] = {"t", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  std::vector<PoseRow> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string_view s = trim(line);
    if (s.empty() || s.front() == '#') continue;
    double v[8];
    std::istringstream fields{std::string(s)};
    std::string tok;
    int k = 0;
    while (fields >> tok) {
      if (k >= 8) throw InputError(path, n, "", "TUM line has more than 8 fields");
      if (!parse_double(tok, v[k]) || !std::isfinite(v[k]))
        throw InputError(path, n, names[k], "not a number: '" + tok + "'");
      ++k;
    }
    if (k != 8)
      throw InputError(path, n, names[k], "TUM line has " + std::to_string(k) + " fields, expected 8 (t tx ty tz qx qy qz qw)");
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-6)) throw InputError(path, n, "qw", "quaternion has zero norm");
    q.normalize();
    out.push_back({checked_time(path, n, v[0]), {v[1], v[2], v[3]}, yaw_of(q)});
  }
  return out;
}

// True when the first data line of the file starts with a number (TUM, no header).
bool looks_like_tum(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::string_view s = trim(line);
    if (first && s.size() >= 3 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
    first = false;
    if (s.empty() || s.front() == '#') continue;
    const auto end = s.find_first_of(" \t,");
    double v = 0;
    return parse_double(s.substr(0, end), v) && s.find(',') == std::string_view::npos;
  }
  return false;
}

}  // namespace

std::vector<TruthRow> read_truth_csv(const std::string& path) {
  CsvReader r(path);
  std::vector<TruthRow> rows = read_csv_trajectory(r, true);
  if (rows.size() < 2)
    throw InputError(path, 0, "", "ground truth needs at least 2 rows, found " + std::to_string(rows.size()));
  return rows;
}

std::vector<PoseRow> read_pose_file(const std::string& path) {
  std::vector<PoseRow> rows;
  if (looks_like_tum(path)) {
    rows = read_tum(path);
  } else {
    // An empty file has no header: report it as what it is.
    try {
      CsvReader r(path);
      rows = read_csv_trajectory(r, false);
    } catch (const InputError& e) {
      if (std::string_view(e.what()).find("no header row") == std::string_view::npos) throw;
    }
  }
  if (rows.empty()) throw InputError(path, 0, "", "no poses in the file");
  return rows;
}

}  // namespace luxloc
