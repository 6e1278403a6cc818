// `luxloc record --source ... --out DIR`: records live sources into a SPEC.md session folder
// that `luxloc run --playback DIR` replays bit for bit (plugins/record/session_recorder.*).
// SIGINT / SIGTERM end the recording cleanly with every file complete.
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "app/run_session.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/record/session_recorder.hpp"

namespace luxloc::app {
namespace {

struct RecordArgs {
  RunConfig run;  // sources, --map, --camera, --clock-offset
  std::string out;
  std::size_t queue = RecorderOptions{}.queue_capacity;
};

int run_record(const RecordArgs& a) {
  OpenedSources opened = open_run_sources(a.run);
  PlaybackSession& session = opened.session;
  RecorderOptions ro;
  ro.queue_capacity = a.queue;
  SessionRecorder recorder(a.out, session.map, session.camera, session.config, ro);
  Pipeline pipeline(std::move(session.sources), {}, opened.pipeline);
  std::cerr << "luxloc record: recording to " << a.out << " (Ctrl-C to stop)\n";
  const PipelineReport report = run_with_stop_signals(pipeline, recorder);
  std::vector<PoseEstimate> none;
  recorder.finish(none);
  const RecorderStats st = recorder.stats();

  std::cerr << "luxloc record: " << (report.stopped ? "stopped" : "done") << " after " << report.data_span_s()
            << " s of data (" << report.wall_s << " s wall)\n";
  for (const auto& s : report.sources) {
    std::cerr << "  source " << s.name << ": " << s.samples << " samples";
    for (const auto& [reason, e] : s.drops) std::cerr << ", " << e.count << " dropped (" << reason << ")";
    std::cerr << "\n";
    if (!s.failure.empty()) std::cerr << "    FAILED: " << s.failure << "\n";
  }
  for (const auto& [file, n] : st.written) std::cerr << "  wrote " << file << ": " << n << " rows\n";
  for (const auto& [file, n] : st.dropped)
    std::cerr << "  DROPPED " << n << " samples for " << file << " (the disk did not keep up)\n";
  std::string failures;
  for (const auto& s : report.sources)
    if (!s.failure.empty()) failures += s.name + ": " + s.failure + "\n";
  if (!failures.empty()) {
    std::cerr << "luxloc: runtime failure:\n" << failures;
    return 1;
  }
  return 0;
}

}  // namespace

void add_record_command(CLI::App& root, Action& action) {
  auto a = std::make_shared<RecordArgs>();
  std::string kinds;
  for (const auto& k : live_source_kinds()) kinds += (kinds.empty() ? "" : ", ") + k;
  CLI::App* sub = root.add_subcommand("record", "record live sources into a session folder (replay with run --playback)");
  sub->add_option("--source", a->run.sources, "live source KIND:TARGET[,key=value...] (repeatable); kinds: " + kinds)
      ->required()
      ->type_name("SPEC");
  sub->add_option("--out", a->out, "new session folder to write")->required()->type_name("DIR");
  sub->add_option("--plugin", a->run.plugins, "load an external source plugin (C ABI); repeatable")->type_name("PATH.so");
  sub->add_option("--map", a->run.map, "LED map to store with the session")->type_name("FILE");
  sub->add_option("--camera", a->run.camera, "camera file to store with the session")->type_name("FILE");
  sub->add_option("--clock-offset", a->run.clock_offsets, "add SECONDS to every time stamp of a source")
      ->type_name("SOURCE=SECONDS");
  sub->add_option("--queue", a->queue, "samples buffered towards the disk before drops are counted")
      ->check(CLI::Range(16, 1'000'000))
      ->capture_default_str();
  sub->callback([a, &action] { action = [a] { return run_record(*a); }; });
}

}  // namespace luxloc::app
