// luxloc: real-time indoor positioning (VLC + IMU + UWB + VO fusion). See README.md.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>
#include <algorithm>
#include <csignal>

#include "app/commands.hpp"
#include "core/common/input_error.hpp"

namespace {

// `luxloc run --config FILE ...` reads like `luxloc --config FILE run ...`: CLI11 takes the
// config file at the root (its [run] section holds run's options), so move it there.
std::vector<std::string> hoist_config(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc), hoisted;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--config" && i + 1 < args.size()) {
      hoisted = {args[i], args[i + 1]};
      args.erase(args.begin() + static_cast<std::ptrdiff_t>(i), args.begin() + static_cast<std::ptrdiff_t>(i) + 2);
      break;
    }
    if (args[i].rfind("--config=", 0) == 0) {
      hoisted = {args[i]};
      args.erase(args.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  }
  args.insert(args.begin(), hoisted.begin(), hoisted.end());
  return args;
}

}  // namespace

int main(int argc, char** argv) {
  // A closed output pipe (`luxloc run --out - | head`) is then a write error (EPIPE) that
  // the outputs report with exit 1, not a silent death by SIGPIPE (plugins/output/text_file).
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App root{"luxloc — real-time indoor positioning: visible light, IMU, UWB and vision fusion"};
  root.set_version_flag("--version", std::string("luxloc ") + LUXLOC_VERSION);
  root.require_subcommand(1);
  root.set_config("--config", "", "read options from a TOML/INI config file");
  luxloc::app::Action action;
  luxloc::app::add_run_command(root, action);
  luxloc::app::add_demo_command(root, action);
  luxloc::app::add_sim_command(root, action);
  luxloc::app::add_eval_command(root, action);
  luxloc::app::add_imu_command(root, action);
  luxloc::app::add_calib_command(root, action);
  luxloc::app::add_bench_command(root, action);
  luxloc::app::add_compare_command(root, action);
  luxloc::app::add_record_command(root, action);
  luxloc::app::add_devices_command(root, action);
  luxloc::app::add_vlc_command(root, action);
  try {
    root.name("luxloc");
    std::vector<std::string> args = hoist_config(argc, argv);
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last to first
    root.parse(args);
  } catch (const CLI::ParseError& e) {
    const int rc = root.exit(e);
    return rc == 0 ? 0 : 2;  // SPEC: bad usage -> 2
  }
  try {
    return action ? action() : 0;
  } catch (const luxloc::InputError& e) {
    std::cerr << "luxloc: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "luxloc: runtime failure: " << e.what() << "\n";
    return 1;
  }
}
