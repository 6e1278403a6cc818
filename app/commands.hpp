#pragma once
// Each subcommand lives in its own app/cmd_*.cpp and registers itself on the root app.
// A subcommand's callback stores the work to do in `action`; main() runs it after
// parsing, so exceptions map to SPEC.md exit codes in one place (InputError -> 2).
#include <CLI/CLI.hpp>
#include <functional>

namespace luxloc::app {

using Action = std::function<int()>;

void add_run_command(CLI::App& root, Action& action);
void add_demo_command(CLI::App& root, Action& action);
void add_sim_command(CLI::App& root, Action& action);
void add_eval_command(CLI::App& root, Action& action);
void add_imu_command(CLI::App& root, Action& action);
void add_calib_command(CLI::App& root, Action& action);
void add_bench_command(CLI::App& root, Action& action);
void add_compare_command(CLI::App& root, Action& action);
void add_record_command(CLI::App& root, Action& action);
// `calib ledmap` (app/cmd_calib_ledmap.cpp), registered under `calib`.
void add_calib_ledmap(CLI::App& calib, Action& action);
// `calib ledmap plan` (app/cmd_calib_ledmap_plan.cpp), registered under `calib ledmap`.
void add_calib_ledmap_plan(CLI::App& ledmap, Action& action);
// `calib rowtime` (app/cmd_calib_rowtime.cpp), registered under `calib`.
void add_calib_rowtime(CLI::App& calib, Action& action);
// `calib uwb` (app/cmd_calib_uwb.cpp), registered under `calib`.
void add_calib_uwb(CLI::App& calib, Action& action);
// `bench soak` (app/cmd_bench_soak.cpp), registered under `bench`.
void add_bench_soak(CLI::App& bench, Action& action);
// `bench live` (app/cmd_bench_live.cpp), registered under `bench`.
void add_bench_live(CLI::App& bench, Action& action);
void add_devices_command(CLI::App& root, Action& action);
void add_vlc_command(CLI::App& root, Action& action);

}  // namespace luxloc::app
