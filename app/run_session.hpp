#pragma once
// Shared by `run` and `demo`: builds the sources, the fusion stage and the sinks from the
// options, runs the pipeline and reports what happened.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "core/fusion/fusion_engine.hpp"
#include "core/pipeline/pipeline.hpp"

namespace luxloc::app {

struct RunConfig {
  std::vector<std::string> sources;  // --source KIND:TARGET[,k=v...]
  std::string playback;              // --playback DIR (= --source playback:DIR)
  std::string map, camera;           // overrides of the session's files
  FusionOptions fusion;
  UwbOptions uwb;
  VoOptions vo;
  std::string uwb_likelihood = "robust";  // robust | gaussian
  std::string resampling = "systematic";
  std::string coupling = "tight";    // tight | loose
  std::string out;                   // pose file; "-" = stdout; empty and no --udp: stdout
  std::vector<std::string> udp;      // HOST:PORT, repeatable
  std::string format = "csv";        // csv | tum
  bool realtime = false;
  int threads = 0;                   // 0 = all cores (TBB default)
  std::vector<std::string> clock_offsets;  // SOURCE=SECONDS
  bool quiet = false;
};

struct RunOutcome {
  PipelineReport pipeline;
  FusionStats fusion;
  UwbStats uwb;
  VoStats vo;
  std::optional<std::filesystem::path> groundtruth;  // of the played-back session
  std::string failures;  // sources that ended through a failure
};

// Registers the options of `run` on `sub` (also used by `demo` for a subset).
void add_run_options(CLI::App* sub, RunConfig& cfg);
// Runs the session; SIGINT/SIGTERM stop it cleanly (every computed pose is written).
// Throws InputError for unusable options or input files.
RunOutcome run_session(const RunConfig& cfg, std::ostream& log);
// The end-of-run report: per-source samples and drops, fusion counters, speed.
void print_report(const RunOutcome& r, std::ostream& log);

}  // namespace luxloc::app
