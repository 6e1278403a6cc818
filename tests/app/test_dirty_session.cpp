// Dirty sessions (issue 13, "Done when" 1): a simulated walk played back clean and with the
// faults of the two dirty sessions of the issue rebuilt by hand — garbage IMU rows (1e30 and
// -1e30 in every IMU column, each with the time stamp of the good row next to it, NaN, text,
// a time of 1e30, a short row), swapped rows, a frame line pointing at a missing file, a PNG
// and a JPEG cut in half. The dirty run must cost no more than its bad samples: ATE within
// 1.2x of the clean run, the same step count, no re-initialisation the clean run does not
// have, every bad row and frame named by reason with file and line, no image-library noise.
#include <catch2/catch.hpp>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

void write_lines(const fs::path& p, const std::vector<std::string>& lines) {
  std::ofstream out(p);
  for (const auto& l : lines) out << l << "\n";
}

std::vector<std::string> split(const std::string& row) {
  std::vector<std::string> f;
  std::stringstream s(row);
  for (std::string x; std::getline(s, x, ',');) f.push_back(x);
  return f;
}

std::string join(const std::vector<std::string>& f) {
  std::string r;
  for (std::size_t i = 0; i < f.size(); ++i) r += (i ? "," : "") + f[i];
  return r;
}

long long count_in_report(const std::string& text, const std::string& re) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(re))) return -1;
  return std::stoll(m[1]);
}

struct RunResult {
  std::string report;
  EvalResult eval;
  long long steps = -1, reinits = -1;
};

RunResult play(const fs::path& session, const fs::path& truth, const fs::path& poses) {
  const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "' --seed 3");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  RunResult r;
  r.report = run.output;
  r.eval = evaluate(read_truth_csv(truth.string()), read_pose_file(poses.string()));
  r.steps = count_in_report(run.output, R"(, (\d+) steps)");
  r.reinits = count_in_report(run.output, R"(gated, (\d+) re-initialisations)");
  return r;
}

// A bad row expected in the report: "<reason>: ...<file>:<line>: field '<field>'".
struct Expected {
  std::string reason, file;
  std::size_t line = 0;  // 1-based
  std::string field;
};

}  // namespace

TEST_CASE("A dirty session costs no more than its bad samples, each named by reason, file and line",
          "[e2e][dirty]") {
  const fs::path dir = test::scratch_dir("e2e_dirty_session");
  const fs::path clean = dir / "clean", dirty = dir / "dirty";
  const auto sim = run_luxloc("sim --out '" + clean.string() + "' --scenario walk --duration 60 --seed 11");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);

  // The dirty copy: the same map, camera, truth; its own imu.csv and frames.csv, whose
  // good frames point at the clean session's images (absolute paths, SPEC allows them).
  fs::create_directories(dirty / "frames");
  for (const char* f : {"ledmap.yaml", "camera.yaml", "session.yaml", "groundtruth.csv"})
    if (fs::exists(clean / f)) fs::copy_file(clean / f, dirty / f);

  std::vector<Expected> expected;
  // imu.csv: header t,ax,ay,az,gx,gy,gz,mx,my,mz (the simulator writes the magnetometer).
  const std::vector<std::string> imu = lines_of(clean / "imu.csv");
  REQUIRE(imu.size() > 5000);
  REQUIRE(imu[0] == "t,ax,ay,az,gx,gy,gz,mx,my,mz");
  const std::vector<std::string> cols = split(imu[0]);
  std::vector<std::string> out = {imu[0]};
  std::size_t garbage = 0;
  // Good rows 300, 500, 700...: 18 rows with +-1e30 in one IMU column each (all nine
  // columns, both signs), carrying the time stamp of the good row after them (the case that
  // made the reader drop the good row as a "duplicate time" and fuse the impossible one).
  std::size_t next_bad = 300, bad_index = 0;
  const std::size_t swap_a = 2150, swap_b = 4020;  // rows swapped with their successor
  for (std::size_t k = 1; k < imu.size(); ++k) {
    if (k == next_bad && bad_index < 18) {
      std::vector<std::string> f = split(imu[k]);
      const std::size_t col = 1 + bad_index % 9;
      f[col] = bad_index < 9 ? "1e30" : "-1e30";
      out.push_back(join(f));
      expected.push_back({"out of range", "imu.csv", out.size(), cols[col]});
      ++garbage;
      ++bad_index;
      next_bad += 200;
    }
    if (k == 1500) {  // NaN in a gyro column, same time as the good row
      std::vector<std::string> f = split(imu[k]);
      f[5] = "nan";
      out.push_back(join(f));
      expected.push_back({"bad row", "imu.csv", out.size(), "gy"});
      ++garbage;
    }
    if (k == 2500) {  // text
      out.push_back("@@@garbage, not a row");
      expected.push_back({"bad row", "imu.csv", out.size(), "t"});
      ++garbage;
    }
    if (k == 3300) {  // a time of 1e30
      std::vector<std::string> f = split(imu[k]);
      f[0] = "1e30";
      out.push_back(join(f));
      expected.push_back({"bad row", "imu.csv", out.size(), "t"});
      ++garbage;
    }
    if (k == 4500) {  // too few fields
      out.push_back(split(imu[k])[0] + ",0.1,0.2");
      expected.push_back({"bad row", "imu.csv", out.size(), "az"});
      ++garbage;
    }
    if (k == swap_a || k == swap_b) {
      out.push_back(imu[k + 1]);
      out.push_back(imu[k]);
      expected.push_back({"out of order", "imu.csv", out.size(), "t"});
      ++k;
      continue;
    }
    out.push_back(imu[k]);
    if (k == 5200) {  // 1e30 rad/s after the good row, with its time stamp
      std::vector<std::string> f = split(imu[k]);
      f[6] = "1e30";
      out.push_back(join(f));
      expected.push_back({"out of range", "imu.csv", out.size(), "gz"});
      ++garbage;
    }
  }
  write_lines(dirty / "imu.csv", out);
  CHECK(garbage == 23);

  // frames.csv: absolute paths to the clean frames, one line pointing at a missing file, one
  // at a PNG cut in half, one at a JPEG cut in half.
  const std::vector<std::string> frames = lines_of(clean / "frames.csv");
  REQUIRE(frames.size() > 1000);
  std::vector<std::string> fout = {frames[0]};
  for (std::size_t k = 1; k < frames.size(); ++k) {
    std::vector<std::string> f = split(frames[k]);
    const fs::path image = clean / f[1];
    if (k == 400) {
      f[1] = "frames/missing.jpg";
      expected.push_back({"missing frame", "frames.csv", k + 1, "file"});
    } else if (k == 900 || k == 1300) {
      const cv::Mat gray = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
      REQUIRE(!gray.empty());
      std::vector<std::uint8_t> bytes;
      const std::string ext = k == 900 ? ".png" : ".jpg";
      REQUIRE(cv::imencode(ext, gray, bytes));
      bytes.resize(bytes.size() / 2);
      const std::string name = "frames/cut" + std::to_string(k) + ext;
      std::ofstream((dirty / name).string(), std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      f[1] = name;
      expected.push_back({"bad frame", "frames.csv", k + 1, "file"});
    } else {
      f[1] = image.string();
    }
    fout.push_back(join(f));
  }
  write_lines(dirty / "frames.csv", fout);

  const RunResult c = play(clean, clean / "groundtruth.csv", dir / "clean.csv");
  const RunResult d = play(dirty, dirty / "groundtruth.csv", dir / "dirty.csv");
  INFO(d.report);
  WARN("clean: ATE " << c.eval.rmse_m << " m, max " << c.eval.max_m << ", " << c.steps << " steps, " << c.reinits
                     << " re-initialisations; dirty: ATE " << d.eval.rmse_m << " m, max " << d.eval.max_m << ", "
                     << d.steps << " steps, " << d.reinits << " re-initialisations");
  CHECK(d.eval.rmse_m <= 1.2 * c.eval.rmse_m);
  CHECK(d.eval.max_m <= 1.5 * c.eval.max_m + 0.02);
  CHECK(d.eval.coverage >= c.eval.coverage - 0.01);
  REQUIRE(c.steps > 50);
  CHECK(d.steps == c.steps);
  CHECK(d.reinits <= c.reinits);

  // Counted by reason...
  CHECK(count_in_report(d.report, R"(playback:imu: \d+ samples[^\n]*, (\d+) skipped \(out of range\))") == 19);
  CHECK(count_in_report(d.report, R"(playback:imu: \d+ samples[^\n]*, (\d+) skipped \(bad row\))") == 4);
  CHECK(count_in_report(d.report, R"(playback:imu: \d+ samples[^\n]*, (\d+) skipped \(out of order\))") == 2);
  CHECK(d.report.find("duplicate time") == std::string::npos);  // no good row lost to a bad one
  CHECK(count_in_report(d.report, R"(playback:frames: \d+ samples[^\n]*, (\d+) skipped \(missing frame\))") == 1);
  CHECK(count_in_report(d.report, R"(playback:frames: \d+ samples[^\n]*, (\d+) skipped \(bad frame\))") == 2);
  // ... each named with file, line and field.
  for (const Expected& e : expected) {
    const std::string re = e.reason + ": [^\\n]*" + e.file + ":" + std::to_string(e.line) + ": field '" + e.field + "'";
    INFO("expected in the report: " << re);
    CHECK(std::regex_search(d.report, std::regex(re)));
  }
  CHECK(expected.size() == 28);
  // The image libraries say nothing of their own.
  CHECK(d.report.find("libpng") == std::string::npos);
  CHECK(d.report.find("Corrupt JPEG") == std::string::npos);
  CHECK(d.report.find("premature end") == std::string::npos);
}
