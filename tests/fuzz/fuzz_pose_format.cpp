// libFuzzer target: the pose formatters (plugins/output): the JSON datagram of --udp, the
// CSV row and the TUM line, for any bit pattern in every field (NaN, infinities, 1e308,
// denormals, the extremes of the ns timeline). Round trip: the JSON is one flat object
// whose numbers parse back to the pose within the printed precision, with unknown values
// omitted (never nan/inf/null); the CSV row has exactly 15 fields, empty exactly where
// the value is not finite; the TUM line is empty exactly when the pose cannot be written
// and otherwise holds a unit quaternion with qw >= 0.
#include <cstring>
#include <map>

#include "plugins/output/pose_file_sinks.hpp"
#include "plugins/output/udp_pose_sink.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

namespace {

struct Reader {
  const std::uint8_t* p;
  std::size_t n;
  template <class T>
  T take() {
    T v{};
    const std::size_t k = std::min(sizeof(T), n);
    std::memcpy(&v, p, k);
    p += k;
    n -= k;
    return v;
  }
};

// A flat JSON object of numbers: {"key":number,...}. Fails on anything else.
std::map<std::string, double> parse_flat_json(const std::string& s) {
  std::map<std::string, double> out;
  if (s.size() < 2 || s.front() != '{' || s.back() != '}') fuzz::fail("JSON is not an object: " + s);
  std::size_t i = 1;
  while (i < s.size() - 1) {
    if (s[i] != '"') fuzz::fail("JSON key not quoted: " + s);
    const std::size_t q = s.find('"', i + 1);
    const std::string key = s.substr(i + 1, q - i - 1);
    if (q == std::string::npos || s[q + 1] != ':') fuzz::fail("JSON key without ':': " + s);
    const char* start = s.c_str() + q + 2;
    char* end = nullptr;
    const double v = std::strtod(start, &end);
    if (end == start || !std::isfinite(v)) fuzz::fail("JSON value not a finite number: " + s);
    if (!out.emplace(key, v).second) fuzz::fail("JSON key twice: " + key);
    i = static_cast<std::size_t>(end - s.c_str());
    if (s[i] == ',') ++i;
    else if (i != s.size() - 1) fuzz::fail("JSON garbage after a value: " + s);
  }
  return out;
}

void expect_close(const std::map<std::string, double>& j, const char* key, double v, double tol) {
  const auto it = j.find(key);
  if (!std::isfinite(v)) {
    if (it != j.end()) fuzz::fail(std::string("non-finite value written for ") + key);
    return;
  }
  if (it == j.end()) fuzz::fail(std::string("finite value omitted: ") + key);
  if (std::abs(it->second - v) > tol + std::abs(v) * 1e-15) fuzz::fail(std::string("round trip off: ") + key);
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> f(1);
  for (char c : line) {
    if (c == sep) f.emplace_back();
    else f.back() += c;
  }
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader r{data, size};
  PoseEstimate p;
  p.t = r.take<std::int64_t>();
  p.p_BinW = {r.take<double>(), r.take<double>(), r.take<double>()};
  p.yaw = r.take<double>();
  p.roll = r.take<double>();
  p.pitch = r.take<double>();
  p.sigma_x = r.take<double>();
  p.sigma_y = r.take<double>();
  p.n_eff = r.take<double>();
  p.leds = r.take<int>();
  const std::uint64_t seq = r.take<std::uint64_t>();
  p.mode.assign(reinterpret_cast<const char*>(r.p), std::min<std::size_t>(r.n, 64));
  // The motion column's text: the input's last bytes (commas and line breaks included).
  const std::size_t motion_n = std::min<std::size_t>(r.n, 32);
  p.motion.assign(reinterpret_cast<const char*>(r.p) + (r.n - motion_n), motion_n);

  const std::string json = pose_json(p, seq);
  const auto j = parse_flat_json(json);
  expect_close(j, "t", static_cast<double>(p.t) * 1e-9, 1e-6);
  expect_close(j, "x", p.p_BinW.x(), 1e-5);
  expect_close(j, "y", p.p_BinW.y(), 1e-5);
  expect_close(j, "z", p.p_BinW.z(), 1e-5);
  expect_close(j, "yaw", p.yaw, 1e-5);
  expect_close(j, "sigma_x", p.sigma_x, 1e-5);
  expect_close(j, "sigma_y", p.sigma_y, 1e-5);
  expect_close(j, "n_eff", p.n_eff, 0.1);
  expect_close(j, "leds", p.leds, 0.0);
  expect_close(j, "seq", static_cast<double>(seq), 0.0);

  const std::string row = pose_csv_row(p);
  if (row.empty() || row.back() != '\n') fuzz::fail("CSV row without its newline");
  const auto fields = split(row.substr(0, row.size() - 1), ',');
  if (row.find_first_of("\r\n") != row.size() - 1) fuzz::fail("CSV row with a line break inside: " + row);
  if (fields.size() != 15) fuzz::fail("CSV row with " + std::to_string(fields.size()) + " fields: " + row);
  const double values[] = {p.p_BinW.x(), p.p_BinW.y(), p.p_BinW.z(), p.yaw, p.sigma_x, p.sigma_y, p.roll, p.pitch, p.n_eff};
  for (int k = 0; k < 9; ++k)
    if (fields[1 + k].empty() == std::isfinite(values[k])) fuzz::fail("CSV field " + std::to_string(1 + k) + " wrong: " + row);
  if (fields[12].empty() == std::isfinite(p.sigma_yaw)) fuzz::fail("CSV field 12 (sigma_yaw) wrong: " + row);
  if (fields[13].empty() == std::isfinite(p.sigma_z)) fuzz::fail("CSV field 13 (sigma_z) wrong: " + row);

  const std::string tum = pose_tum_line(p);
  const bool writable = p.p_BinW.allFinite();  // an unknown yaw is written as the identity
  if (tum.empty() == writable) fuzz::fail("TUM line " + std::string(tum.empty() ? "missing" : "written") + " for this pose");
  if (!tum.empty()) {
    const auto f = split(tum.substr(0, tum.size() - 1), ' ');
    if (f.size() != 8) fuzz::fail("TUM line with " + std::to_string(f.size()) + " fields: " + tum);
    const double qx = std::stod(f[4]), qy = std::stod(f[5]), qz = std::stod(f[6]), qw = std::stod(f[7]);
    if (std::abs(qx * qx + qy * qy + qz * qz + qw * qw - 1.0) > 1e-4 || qw < 0.0) fuzz::fail("TUM quaternion not unit / qw < 0: " + tum);
  }
  return 0;
}
