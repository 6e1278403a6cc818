// `luxloc run`: live or playback fusion (SPEC.md "Command line").
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/run_session.hpp"

namespace luxloc::app {
namespace {

// TOML for CLI11's config reader: one line per option, its description above it; options
// without a value (unset, no default) are written commented out.
std::string dump_config(const CLI::App& sub) {
  const auto quoted = [](const std::string& v) {
    std::string q(1, '"');
    for (char ch : v) {
      if (ch == '"' || ch == '\\') q.push_back('\\');
      q.push_back(ch);
    }
    q.push_back('"');
    return q;
  };
  std::ostringstream out;
  out << "# luxloc run: effective configuration. Use: luxloc --config FILE run [flags that override it]\n";
  out << "[" << sub.get_name() << "]\n";
  for (const CLI::Option* o : sub.get_options()) {
    const std::string name = o->get_single_name();
    if (o->get_lnames().empty() || name == "help" || name == "dump-config") continue;
    out << "\n# " << o->get_description() << "\n";
    std::vector<std::string> values = o->results();
    if (values.empty() && !o->get_default_str().empty()) values.push_back(o->get_default_str());
    if (o->get_expected_max() == 0) {  // a flag, as its own name says it: `--no-uwb=false` is off
      // A negated flag ("!--no-uwb") stores the bound value (false when given), the others
      // what was given; as<bool> reads either.
      const bool negated = o->get_flag_value(name, "") == "false";
      out << name << "=" << (o->count() > 0 && o->as<bool>() != negated ? "true" : "false") << "\n";
    } else if (values.empty()) {
      out << "# " << name << "=\n";
    } else if (o->get_expected_max() > 1 || values.size() > 1) {
      out << name << "=[";
      for (std::size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << quoted(values[i]);
      out << "]\n";
    } else {
      out << name << "=" << quoted(values.front()) << "\n";
    }
  }
  return out.str();
}

// Why a run wrote no pose (issue 12: never a silent 0 poses): the filter starts at the first
// absolute position or at a known start, and this run had neither.
std::string no_poses_explanation(const RunOutcome& r) {
  const FusionStats& f = r.fusion;
  std::ostringstream s;
  s << "luxloc: no poses written: the filter never started. It starts at the first absolute position "
       "(camera frames showing LEDs of the map, fixes.csv, UWB ranges to known anchors) or at a known start "
       "(--start X,Y[,YAW], or start: {x, y, yaw} in session.yaml). This run had " << f.imu_samples
    << " IMU samples, " << f.frames << " camera frames (" << f.frames_with_leds << " with LEDs identified), "
    << r.uwb.samples << " UWB measurements and no usable fix.\n";
  if (f.frames > 0 && f.frames_with_leds == 0)
    s << "  the camera frames showed no LED of the map: a missing or wrong ledmap.yaml/camera.yaml "
         "(--map, --camera), or the lights were off\n";
  if (r.uwb.samples > 0 && r.uwb.unknown_anchor > 0)
    s << "  " << r.uwb.unknown_anchor << " UWB measurements came from anchors not in session.yaml's `anchors` list\n";
  if (f.imu_samples > 0 && f.frames == 0 && r.uwb.samples == 0)
    s << "  only an IMU: give the start pose (--start X,Y[,YAW]) for dead reckoning\n";
  return s.str();
}

}  // namespace

void add_run_command(CLI::App& root, Action& action) {
  auto cfg = std::make_shared<RunConfig>();
  CLI::App* sub = root.add_subcommand("run", "fuse live sensors or a recorded session and output poses");
  add_run_options(sub, *cfg);
  // `luxloc run ... --dump-config > run.toml` writes the effective options as a [run]
  // section that `luxloc --config run.toml run` reads back (flags given then win).
  auto dump = std::make_shared<bool>(false);
  sub->add_flag("--dump-config", *dump, "print the effective configuration (TOML, every option) and exit");
  sub->callback([cfg, dump, sub, &action] {
    if (*dump) {
      action = [sub] {
        std::cout << dump_config(*sub);
        return 0;
      };
      return;
    }
    action = [cfg] {
      const RunOutcome r = run_session(*cfg, std::cerr);
      if (!r.failures.empty()) {
        std::cerr << "luxloc: runtime failure:\n" << r.failures;
        return 1;
      }
      if (r.pipeline.poses == 0 && !r.pipeline.stopped) {
        std::cerr << no_poses_explanation(r);
        return 2;
      }
      return 0;
    };
  });
}

}  // namespace luxloc::app
