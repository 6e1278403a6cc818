// luxloc: real-time indoor positioning (VLC + IMU + UWB + VO fusion). See README.md.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>

#include "app/commands.hpp"
#include "core/common/input_error.hpp"

int main(int argc, char** argv) {
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
  luxloc::app::add_devices_command(root, action);
  luxloc::app::add_vlc_command(root, action);
  try {
    root.parse(argc, argv);
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
