// libFuzzer target: the TOML/INI config file (`luxloc --config FILE`, read by CLI11 into the
// same command tree as the binary: app/cli). The input's first line is the subcommand, the
// rest the config file. Parsing ends in the subcommand's options or a CLI11 ParseError /
// InputError (exit 2 with a message); nothing else may escape. The parsed action is not run.
#include "app/cli.hpp"
#include "core/common/input_error.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = in.find('\n');
  if (eol == std::string_view::npos || eol > 40) return 0;
  const std::string command(in.substr(0, eol));
  static const std::vector<std::string> kCommands = {"run", "sim", "eval", "imu", "vlc", "compare", "record", "demo"};
  if (std::find(kCommands.begin(), kCommands.end(), command) == kCommands.end()) return 0;
  const std::string path = (fuzz::scratch() / "config.toml").string();
  fuzz::write_file(path, in.substr(eol + 1));

  // The command tree is built once: building it (hundreds of options) was 2/3 of each
  // execution (110 executions a second). CLI::App::clear() resets every parse result, so
  // each input is parsed as by a fresh tree; option values bound inside the tree are
  // overwritten by the next parse of that subcommand.
  static app::Action action;
  static CLI::App& root = []() -> CLI::App& {
    static CLI::App app{"luxloc"};
    app::build_cli(app, action);
    return app;
  }();
  root.clear();
  action = nullptr;
  std::vector<std::string> args = app::hoist_config({command, "--config", path});
  std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last to first
  try {
    root.parse(args);
  } catch (const CLI::ParseError&) {
  } catch (const InputError&) {
  }
  return 0;
}
