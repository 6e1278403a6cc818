#pragma once
// The luxloc command line: the root app with every subcommand and the --config file
// option (TOML/INI, read by CLI11). main() and the config fuzz target (tests/fuzz) build
// the same tree, so the fuzzer parses config files exactly as the binary does.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/commands.hpp"

namespace luxloc::app {

// Registers every subcommand and --config on `root`; a parsed subcommand stores its work in `action`.
void build_cli(CLI::App& root, Action& action);

// `luxloc run --config FILE ...` reads like `luxloc --config FILE run ...`: CLI11 takes the
// config file at the root (its [run] section holds run's options), so move it there.
// `args` are argv without the program name.
std::vector<std::string> hoist_config(std::vector<std::string> args);

}  // namespace luxloc::app
