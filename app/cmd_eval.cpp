// `luxloc eval`: compares a pose file against groundtruth.csv (SPEC.md "Command line").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "core/common/input_error.hpp"
#include "core/eval/trajectory_html.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "core/eval/trajectory_plot.hpp"

namespace luxloc::app {
namespace {

struct EvalArgs {
  std::string truth;
  std::string poses;
  std::string plot;
  std::string html;
  bool json = false;
  double bin_s = 1.0;
  double from_s = -std::numeric_limits<double>::infinity();  // --from: poses at or after (data time, s)
  double to_s = std::numeric_limits<double>::infinity();     // --to: poses at or before
  double settle_m = 0.0;                                     // --settle: report when errors stay below
};

int run_eval(const EvalArgs& a) {
  const std::vector<TruthRow> truth = read_truth_csv(a.truth);
  std::vector<PoseRow> poses = read_pose_file(a.poses);
  if (std::isfinite(a.from_s) || std::isfinite(a.to_s)) {
    if (!(a.from_s < a.to_s)) throw InputError("--from", 0, "--to", "--from must be before --to");
    std::erase_if(poses, [&](const PoseRow& p) { return ns_to_seconds(p.t) < a.from_s || ns_to_seconds(p.t) > a.to_s; });
  }
  EvalOptions options;
  options.coverage_bin_s = a.bin_s;
  const EvalResult r = evaluate(truth, poses, options);
  if (r.n == 0) {
    char span[96];
    std::snprintf(span, sizeof span, "[%.3f, %.3f] s", ns_to_seconds(r.truth_t0), ns_to_seconds(r.truth_t1));
    throw InputError(a.poses, 0, "t",
                     "no poses inside the ground-truth time span " + std::string(span) + " of " + a.truth +
                         " (" + std::to_string(r.n_outside) + " poses, all outside)");
  }
  if (!a.plot.empty()) {
    PlotOptions plot;
    plot.title = "luxloc eval";
    write_trajectory_plot(a.plot, truth, r, plot);
  }
  if (!a.html.empty()) {
    std::ofstream html(a.html, std::ios::binary);
    html << trajectory_report_html(truth, r, "luxloc eval: " + a.poses);
    html.flush();
    if (!html) throw InputError(a.html, 0, "--html", "cannot write the report");
  }
  const double settled = a.settle_m > 0.0 ? settle_time_s(r, a.settle_m) : std::nan("");
  const double t_first = r.errors.empty() ? std::nan("") : ns_to_seconds(r.errors.front().t);
  if (a.json) {
    std::string j = format_eval_json(r);
    if (a.settle_m > 0.0) {
      char extra[160];
      std::snprintf(extra, sizeof extra, ",\"settle_m\":%g,\"settled_t\":%s,\"settled_after_s\":%s}", a.settle_m,
                    std::isfinite(settled) ? std::to_string(settled).c_str() : "null",
                    std::isfinite(settled) ? std::to_string(settled - t_first).c_str() : "null");
      j.pop_back();
      j += extra;
    }
    std::cout << j << "\n";
  } else {
    std::cout << "truth            " << a.truth << " (" << truth.size() << " rows)\n"
              << "poses            " << a.poses << " (" << poses.size() << " rows)\n";
    if (!a.plot.empty()) std::cout << "plot             " << a.plot << "\n";
    if (!a.html.empty()) std::cout << "html             " << a.html << "\n";
    std::cout << format_eval_report(r);
    if (a.settle_m > 0.0) {
      if (std::isfinite(settled))
        std::printf("settled          below %g m from t = %.2f s (%.2f s after the first evaluated pose) to the end\n",
                    a.settle_m, settled, settled - t_first);
      else
        std::printf("settled          never: the last pose is %g m or more off\n", a.settle_m);
    }
  }
  std::cout.flush();
  return 0;
}

}  // namespace

void add_eval_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = root.add_subcommand(
      "eval", "compare a pose file with groundtruth.csv: ATE RMSE, median, p95, max horizontal error, coverage");
  cmd->add_option("--truth", args->truth, "ground truth CSV (t,x,y[,z,yaw])")->required()->check(CLI::ExistingFile);
  cmd->add_option("poses", args->poses,
                  "pose file: luxloc CSV output (columns t,x,y[,z,yaw] found by name) or TUM "
                  "(t tx ty tz qx qy qz qw, no header; detected)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--plot", args->plot, "write a PNG: XY truth vs estimate, and error over time");
  cmd->add_option("--html", args->html,
                  "write a static HTML report: trajectory vs truth, error over time, error histogram (no script)");
  cmd->add_flag("--json", args->json, "print the metrics as one JSON object instead of text");
  cmd->add_option("--coverage-bin", args->bin_s, "bin width of the coverage measure, seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--from", args->from_s, "evaluate only poses at or after this time (s, data clock)");
  cmd->add_option("--to", args->to_s, "evaluate only poses at or before this time (s, data clock)");
  cmd->add_option("--settle", args->settle_m,
                  "also report when the error settles: the first time after which it stays below this many metres")
      ->check(CLI::PositiveNumber)
      ->type_name("M");
  cmd->footer(std::string(
                  "Each pose is compared with the truth linearly interpolated at the pose time; poses outside "
                  "the truth time span are ignored and counted. Error = horizontal (x, y) distance, metres; "
                  "no alignment (same world frame). yaw RMSE when both files have yaw (angles wrapped).\n") +
              kCoverageDefinition + " (bin width: --coverage-bin).\n" +
              "Exit 2 on unusable input (file, line and field named), or when no pose lies in the truth span.");
  cmd->callback([&action, args] { action = [args] { return run_eval(*args); }; });
}

}  // namespace luxloc::app
