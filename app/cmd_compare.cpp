// `luxloc compare --playback DIR`: runs the seeds' configurations and ours on one session
// and prints one table (ATE RMSE, median, p95, max, coverage, CPU and wall seconds), so the
// seeds' comparisons (SEEDS.md A: IMU + VLC; B: INS alone, UWB alone, plain PF, genetic PF;
// C: IMU, vision, EKF) can be reproduced on any session that has a groundtruth.csv.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/compare_configs.hpp"
#include "app/run_session.hpp"
#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);  // all threads of the process (TBB workers, source threads)
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct CompareArgs {
  RunConfig base;
  std::vector<std::string> only;
  std::string csv;   // optional: the table as CSV
  std::string keep;  // optional: folder for each configuration's poses
};

struct Row {
  const CompareConfig* config = nullptr;
  EvalResult eval;
  double cpu_s = 0.0, wall_s = 0.0;
  std::uint64_t reinit = 0;
};

std::string fmt(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

int run_compare(const CompareArgs& a) {
  if (a.base.playback.empty()) throw InputError("compare", 0, "--playback", "give the session with --playback DIR");
  const fs::path truth_path = fs::path(a.base.playback) / "groundtruth.csv";
  if (!fs::exists(truth_path))
    throw InputError(truth_path.string(), 0, "", "compare needs the session's ground truth (groundtruth.csv)");
  const std::vector<TruthRow> truth = read_truth_csv(truth_path.string());

  std::vector<const CompareConfig*> chosen;
  for (const CompareConfig& c : compare_configs())
    if (a.only.empty() || std::find(a.only.begin(), a.only.end(), c.name) != a.only.end()) chosen.push_back(&c);
  for (const std::string& name : a.only) {
    bool known = false;
    for (const CompareConfig& c : compare_configs()) known = known || c.name == name;
    if (!known) throw InputError("--only", 0, "--only", "unknown configuration '" + name + "'");
  }

  const fs::path dir = a.keep.empty() ? fs::temp_directory_path() / ("luxloc-compare-" + std::to_string(getpid()))
                                      : fs::path(a.keep);
  fs::create_directories(dir);
  std::vector<Row> rows;
  for (const CompareConfig* c : chosen) {
    RunConfig cfg = a.base;
    c->apply(cfg);
    cfg.out = (dir / (c->name + ".csv")).string();
    cfg.udp.clear();
    cfg.format = "csv";
    cfg.quiet = true;
    std::cerr << "compare: " << c->name << " ..." << std::flush;
    const double cpu0 = process_cpu_s();
    std::ostringstream log;
    const RunOutcome out = run_session(cfg, log);
    Row r;
    r.config = c;
    r.cpu_s = process_cpu_s() - cpu0;
    r.wall_s = out.pipeline.wall_s;
    r.reinit = out.fusion.reinitializations;
    r.eval = evaluate(truth, read_pose_file(cfg.out));
    std::cerr << " ATE " << fmt(r.eval.rmse_m) << " m\n";
    rows.push_back(std::move(r));
  }
  if (a.keep.empty()) fs::remove_all(dir);

  std::printf("session %s (%.1f s of ground truth)\n", a.base.playback.c_str(),
              ns_to_seconds(truth.back().t - truth.front().t));
  std::printf("%-10s %-52s %8s %8s %8s %8s %6s %6s %7s %7s\n", "config", "what", "ATE RMSE", "median", "p95", "max",
              "cover", "reinit", "CPU s", "wall s");
  for (const Row& r : rows)
    std::printf("%-10s %-52s %8s %8s %8s %8s %5.1f%% %6llu %7s %7s\n", r.config->name.c_str(),
                r.config->description.c_str(), fmt(r.eval.rmse_m).c_str(), fmt(r.eval.median_m).c_str(),
                fmt(r.eval.p95_m).c_str(), fmt(r.eval.max_m).c_str(), 100.0 * r.eval.coverage,
                static_cast<unsigned long long>(r.reinit), fmt(r.cpu_s, 2).c_str(), fmt(r.wall_s, 2).c_str());
  std::printf("(errors in metres, horizontal, no alignment; poses cover %s)\n", "the session after initialisation");
  if (!a.csv.empty()) {
    std::ofstream f(a.csv);
    if (!f) throw InputError(a.csv, 0, "--csv", "cannot write");
    f << "config,ate_rmse_m,median_m,p95_m,max_m,coverage,reinitializations,cpu_s,wall_s\n";
    for (const Row& r : rows)
      f << r.config->name << "," << fmt(r.eval.rmse_m, 4) << "," << fmt(r.eval.median_m, 4) << ","
        << fmt(r.eval.p95_m, 4) << "," << fmt(r.eval.max_m, 4) << "," << fmt(r.eval.coverage, 4) << "," << r.reinit
        << "," << fmt(r.cpu_s, 3) << "," << fmt(r.wall_s, 3) << "\n";
  }
  return 0;
}

}  // namespace

void add_compare_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<CompareArgs>();
  std::string names;
  for (const CompareConfig& c : compare_configs()) names += (names.empty() ? "" : ", ") + c.name;
  CLI::App* sub = root.add_subcommand(
      "compare", "run the seeds' filters and the best configuration on one session and print one accuracy table");
  sub->add_option("--playback", args->base.playback, "session folder with groundtruth.csv")->required();
  sub->add_option("--map", args->base.map, "LED map (default: the session's)");
  sub->add_option("--camera", args->base.camera, "camera file (default: the session's)");
  sub->add_option("--particles", args->base.fusion.pf.particles, "particles of the particle filters")
      ->check(CLI::Range(10, 10'000'000))
      ->capture_default_str();
  sub->add_option("--seed", args->base.fusion.pf.seed, "random seed")->capture_default_str();
  sub->add_option("--threads", args->base.threads, "worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  add_particle_filter_options(sub, args->base.fusion.pf);
  sub->add_option("--only", args->only, "run only these configurations (" + names + ")")->delimiter(',');
  sub->add_option("--csv", args->csv, "also write the table as CSV");
  sub->add_option("--keep", args->keep, "keep each configuration's poses in this folder (CONFIG.csv)");
  sub->callback([args, &action] { action = [args] { return run_compare(*args); }; });
}

}  // namespace luxloc::app
