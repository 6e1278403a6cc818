// `luxloc demo`: the embedded default. Fuses the sample session shipped in the repository
// (data/demo-walk, made by `luxloc sim`), writes the poses and prints the accuracy summary.
#include <filesystem>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "app/run_session.hpp"
#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "core/eval/trajectory_plot.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

// The demo session: next to the binary's source tree (build trees), or under an install prefix.
fs::path find_demo_session(const std::string& override_dir) {
  if (!override_dir.empty()) return override_dir;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates = {fs::path(LUXLOC_SOURCE_DIR) / "data" / "demo-walk"};
  if (!ec) {
    candidates.push_back(exe.parent_path() / ".." / "data" / "demo-walk");
    candidates.push_back(exe.parent_path() / ".." / "share" / "luxloc" / "demo-walk");
  }
  for (const auto& c : candidates)
    if (fs::is_directory(c)) return c;
  throw InputError(candidates.front().string(), 0, "", "demo session not found (is the repository complete?)");
}

}  // namespace

void add_demo_command(CLI::App& root, Action& action) {
  struct DemoOptions {
    std::string session;
    std::string out = "demo-poses.csv";
    std::string plot;
    int threads = 0;
  };
  auto opt = std::make_shared<DemoOptions>();
  CLI::App* sub = root.add_subcommand(
      "demo", "fuse the sample session shipped with luxloc (no hardware) and print the accuracy summary");
  sub->add_option("--out", opt->out, "where to write the poses")->capture_default_str();
  sub->add_option("--plot", opt->plot, "also draw truth vs estimate into this PNG");
  sub->add_option("--session", opt->session, "another session folder instead of the shipped one");
  sub->add_option("--threads", opt->threads, "worker threads (0 = all cores)");
  sub->callback([opt, &action] {
    action = [opt] {
      RunConfig cfg;
      cfg.playback = find_demo_session(opt->session).string();
      cfg.out = opt->out;
      cfg.threads = opt->threads;
      std::cout << "luxloc demo: fusing " << cfg.playback << " (IMU + rolling-shutter VLC, particle filter)\n";
      const RunOutcome r = run_session(cfg, std::cout);
      if (!r.failures.empty()) {
        std::cerr << "luxloc: runtime failure:\n" << r.failures;
        return 1;
      }
      std::cout << "poses written to " << opt->out << "\n";
      if (!r.groundtruth) {
        std::cout << "(the session has no groundtruth.csv: no accuracy summary)\n";
        return 0;
      }
      const std::vector<TruthRow> truth = read_truth_csv(r.groundtruth->string());
      const EvalResult e = evaluate(truth, read_pose_file(opt->out));
      std::cout << format_eval_report(e);
      if (!opt->plot.empty()) {
        PlotOptions po;
        po.title = "luxloc demo";
        write_trajectory_plot(opt->plot, truth, e, po);
        std::cout << "plot written to " << opt->plot << "\n";
      }
      return 0;
    };
  });
}

}  // namespace luxloc::app
