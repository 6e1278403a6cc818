#pragma once
// Helpers shared by tests: scratch folders, running the real luxloc binary.
#include <filesystem>
#include <string>

namespace luxloc::test {

// A fresh, empty folder under the build tree's tests/tmp/<name>.
std::filesystem::path scratch_dir(const std::string& name);
// ../shared relative to the source tree (fixtures, real data).
std::filesystem::path shared_dir();

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs the built luxloc binary with `args` (a shell-quoted argument string).
CommandResult run_luxloc(const std::string& args);
// A shell command line through popen (add 2>&1 to capture stderr too).
CommandResult run_command(const std::string& cmd);
std::string read_text(const std::filesystem::path& p);
void write_text(const std::filesystem::path& p, const std::string& text);

}  // namespace luxloc::test
