// `luxloc calib uwb` (issue 16 part 2): per-anchor range bias (and optionally scale) from a
// session with ground truth: the true 3-D distance device -> anchor at each range's time
// (groundtruth.csv, linearly interpolated) against the measured range, a trimmed least-
// squares line per anchor (core/uwb/range_bias_calibration.hpp). Writes the session's
// anchor list with bias_m / scale (--out), which `run` then applies.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.hpp"
#include "core/common/input_error.hpp"
#include "core/common/session_file.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/uwb/range_bias_calibration.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

struct CalibUwbArgs {
  std::string session;
  std::string out;
  RangeCalibrationOptions options;
};

// uwb.csv's t, anchor, range_m columns (found by name).
std::vector<std::tuple<TimeNs, int, double>> read_ranges(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), 0, "", "cannot open");
  std::string line;
  std::getline(in, line);
  std::map<std::string, int> col;
  {
    std::stringstream ss(line);
    std::string name;
    for (int i = 0; std::getline(ss, name, ','); ++i) col[name] = i;
  }
  if (!col.count("t") || !col.count("anchor") || !col.count("range_m"))
    throw InputError(path.string(), 1, "", "needs the columns t, anchor, range_m");
  std::vector<std::tuple<TimeNs, int, double>> out;
  for (std::size_t n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string x;
    while (std::getline(ss, x, ',')) f.push_back(x);
    try {
      out.emplace_back(seconds_to_ns(std::stod(f.at(col["t"]))), std::stoi(f.at(col["anchor"])),
                       std::stod(f.at(col["range_m"])));
    } catch (const std::exception&) {
      throw InputError(path.string(), n, "", "bad row");
    }
  }
  return out;
}

int run_calib_uwb(const CalibUwbArgs& a) {
  const fs::path dir(a.session);
  SessionConfig config = load_session_config((dir / "session.yaml").string());
  if (config.anchors.empty()) throw InputError((dir / "session.yaml").string(), 0, "anchors", "no anchors to calibrate");
  const std::vector<TruthRow> truth = read_truth_csv((dir / config.groundtruth_file).string());
  std::map<int, std::vector<RangePair>> pairs;
  std::size_t k = 0;
  for (const auto& [t, id, range] : read_ranges(dir / config.uwb_file)) {
    while (k + 1 < truth.size() && truth[k + 1].t < t) ++k;
    if (t < truth.front().t || k + 1 >= truth.size()) continue;  // outside the truth
    const double w = static_cast<double>(t - truth[k].t) / static_cast<double>(truth[k + 1].t - truth[k].t);
    const Eigen::Vector3d p = (1.0 - w) * truth[k].p_inW + w * truth[k + 1].p_inW;
    for (const UwbAnchor& an : config.anchors)
      if (an.id == id) pairs[id].push_back({range, (p - an.p_inW).norm()});
  }
  std::printf("anchor   ranges  trimmed   bias_m    scale   residual_m\n");
  int valid = 0;
  for (UwbAnchor& an : config.anchors) {
    const RangeCalibration c = fit_range_calibration(pairs[an.id], a.options);
    if (!c.valid) {
      std::printf("%6d  %7zu  too few ranges: left as it was\n", an.id, pairs[an.id].size());
      continue;
    }
    ++valid;
    an.bias_m = c.bias_m;
    an.scale = c.scale;
    std::printf("%6d  %7zu  %7zu  %+8.4f  %7.5f  %8.4f\n", an.id, c.used, c.trimmed, c.bias_m, c.scale,
                c.residual_sigma_m);
  }
  if (!a.out.empty()) {
    save_session_config(config, a.out);
    std::printf("wrote %s (%d anchors calibrated)\n", a.out.c_str(), valid);
  }
  return valid > 0 ? 0 : 2;
}

}  // namespace

void add_calib_uwb(CLI::App& calib, Action& action) {
  auto args = std::make_shared<CalibUwbArgs>();
  CLI::App* cmd = calib.add_subcommand(
      "uwb", "per-anchor UWB range bias (and scale) from a session with groundtruth.csv (-> session.yaml anchors)");
  cmd->add_option("session", args->session, "session folder (session.yaml with anchors, uwb.csv, groundtruth.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "write the session.yaml with the calibrated anchors here");
  cmd->add_flag("--scale", args->options.fit_scale, "fit a range scale per anchor too (default: bias only)");
  cmd->callback([&action, args] { action = [args] { return run_calib_uwb(*args); }; });
}

}  // namespace luxloc::app
