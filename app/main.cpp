// luxloc: real-time indoor positioning (VLC + IMU + UWB + VO fusion). See README.md.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>
#include <algorithm>
#include <csignal>

#include "app/cli.hpp"
#include "core/common/input_error.hpp"
#include "core/common/memory_trim.hpp"

int main(int argc, char** argv) {
  luxloc::use_one_heap_arena();  // a flat RSS in long runs (core/common/memory_trim.hpp)
  // A closed output pipe (`luxloc run --out - | head`) is then a write error (EPIPE) that
  // the outputs report with exit 1, not a silent death by SIGPIPE (plugins/output/text_file).
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App root{"luxloc — real-time indoor positioning: visible light, IMU, UWB and vision fusion"};
  luxloc::app::Action action;
  luxloc::app::build_cli(root, action);
  try {
    std::vector<std::string> args = luxloc::app::hoist_config({argv + 1, argv + argc});
    std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last to first
    root.parse(args);
  } catch (const CLI::ParseError& e) {
    const int rc = root.exit(e);
    return rc == 0 ? 0 : 2;  // SPEC: bad usage -> 2
  } catch (const std::logic_error& e) {
    // CLI11 converts some values with std::stoll & co (std::invalid_argument, out_of_range):
    // still bad usage, never an abort.
    std::cerr << "luxloc: error: a command-line or config value could not be read (" << e.what() << ")\n";
    return 2;
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
