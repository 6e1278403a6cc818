// `luxloc run`: live or playback fusion (SPEC.md "Command line").
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "app/run_session.hpp"

namespace luxloc::app {

void add_run_command(CLI::App& root, Action& action) {
  auto cfg = std::make_shared<RunConfig>();
  CLI::App* sub = root.add_subcommand("run", "fuse live sensors or a recorded session and output poses");
  add_run_options(sub, *cfg);
  sub->callback([cfg, &action] {
    action = [cfg] {
      const RunOutcome r = run_session(*cfg, std::cerr);
      if (!r.failures.empty()) {
        std::cerr << "luxloc: runtime failure:\n" << r.failures;
        return 1;
      }
      return 0;
    };
  });
}

}  // namespace luxloc::app
