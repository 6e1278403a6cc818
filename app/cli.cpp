// The command-line tree (app/cli.hpp).
#include "app/cli.hpp"

#include <cstddef>

namespace luxloc::app {

void build_cli(CLI::App& root, Action& action) {
  root.set_version_flag("--version", std::string("luxloc ") + LUXLOC_VERSION);
  root.require_subcommand(1);
  root.set_config("--config", "", "read options from a TOML/INI config file");
  add_run_command(root, action);
  add_demo_command(root, action);
  add_sim_command(root, action);
  add_eval_command(root, action);
  add_imu_command(root, action);
  add_calib_command(root, action);
  add_bench_command(root, action);
  add_compare_command(root, action);
  add_record_command(root, action);
  add_devices_command(root, action);
  add_vlc_command(root, action);
  root.name("luxloc");
}

std::vector<std::string> hoist_config(std::vector<std::string> args) {
  std::vector<std::string> hoisted;
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


}  // namespace luxloc::app
