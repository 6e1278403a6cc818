// `luxloc bench live`: the live path's latency and cost. Runs the simulator as a live
// source in real time (default: the dense scenario, 1280x720 at 30 fps with 2-4 LEDs in
// view, IMU at 200 Hz) through the whole run (fusion, outputs) for N seconds and prints
// the latency of the poses (newest input to the outputs: p50, p99, max), the CPU time per
// second of data (getrusage, all threads) and the peak resident memory. The simulator's
// frame rendering runs in the same process, where a camera would cost nothing: its CPU
// time is measured separately (the same frames rendered again after the run) and taken
// out, both figures printed.
#include <sys/resource.h>

#include <cstdio>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/run_session.hpp"
#include "core/sim/simulator.hpp"
#include "plugins/sim/sim_source.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc::app {
namespace {

struct BenchLiveArgs {
  std::string scenario = "dense";
  double duration_s = 20.0;
  int width = 1280, height = 720;
  double fps = 30.0, imu_rate_hz = 200.0;
  std::size_t particles = 0;  // 0: the run's default
  int threads = 0;
  std::vector<std::string> mqtt;  // also publish (cost with a broker, latency with none)
  std::string web;                // also serve the live view (cost with a browser watching)
};

double cpu_s(const rusage& u) {
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int run_bench_live(const BenchLiveArgs& a) {
  std::ostringstream spec;
  spec << "sim:" << a.scenario << ",duration=" << a.duration_s << ",fps=" << a.fps << ",imu_rate=" << a.imu_rate_hz
       << ",width=" << a.width << ",height=" << a.height;
  RunConfig cfg;
  cfg.sources = {spec.str()};
  cfg.out = "/dev/null";
  cfg.quiet = true;
  cfg.status = "off";
  cfg.threads = a.threads;
  if (a.particles) cfg.fusion.pf.particles = a.particles;
  cfg.mqtt = a.mqtt;
  cfg.web = a.web;
  std::string outputs;
  for (const auto& m : a.mqtt) outputs += " --mqtt " + m;
  if (!a.web.empty()) outputs += " --web " + a.web;
  std::printf("luxloc bench live: --source %s%s, in real time, %.0f s\n", spec.str().c_str(), outputs.c_str(), a.duration_s);
  std::fflush(stdout);

  rusage u0{}, u1{};
  getrusage(RUSAGE_SELF, &u0);
  const RunOutcome r = run_session(cfg, std::cerr);
  getrusage(RUSAGE_SELF, &u1);
  const double run_cpu = cpu_s(u1) - cpu_s(u0);
  const double span = r.pipeline.data_span_s();

  // The simulator's own share: render the run's frames again, on this thread.
  const SimSourceOptions so = SimSourceOptions::from_spec(SourceSpec::parse(spec.str()));
  const sim::Simulator simulator(so.scenario_with_camera(), so.sim);
  const double c0 = thread_cpu_s();
  const std::size_t frames = std::min<std::size_t>(simulator.frame_count(), r.fusion.frames);
  for (std::size_t k = 0; k < frames; ++k) (void)simulator.render(k);
  const double render_cpu = thread_cpu_s() - c0;

  const LatencySummary& l = r.pipeline.latency;
  const double per_s = span > 0 ? run_cpu / span : 0.0, render_per_s = span > 0 ? render_cpu / span : 0.0;
  std::printf("  data                    %.1f s: %llu IMU samples, %llu frames (%.2f LEDs identified per frame), %llu poses\n",
              span, static_cast<unsigned long long>(r.fusion.imu_samples), static_cast<unsigned long long>(r.fusion.frames),
              r.fusion.frames ? static_cast<double>(r.fusion.leds_decoded) / static_cast<double>(r.fusion.frames) : 0.0,
              static_cast<unsigned long long>(r.pipeline.poses));
  std::printf("  latency                 p50 %.3f ms, p99 %.3f ms, max %.3f ms (newest input -> outputs, %llu poses)\n",
              1e3 * l.p50_s, 1e3 * l.p99_s, 1e3 * l.max_s, static_cast<unsigned long long>(l.count));
  std::printf("  cpu per second of data  %.3f s (%.1f %% of a core), all threads\n", per_s, 100 * per_s);
  std::printf("    of which the simulator renders frames  %.3f s (%.1f %%), a camera's work\n", render_per_s,
              100 * render_per_s);
  std::printf("    luxloc itself           %.3f s (%.1f %% of a core)\n", per_s - render_per_s, 100 * (per_s - render_per_s));
  std::printf("  peak RSS                %.1f MB\n", static_cast<double>(u1.ru_maxrss) / 1024.0);
  std::uint64_t dropped = r.pipeline.poses_dropped;
  for (const auto& s : r.pipeline.sources)
    for (const auto& [reason, e] : s.drops) dropped += e.count;
  if (dropped) std::printf("  dropped                 %llu samples or poses (fell behind)\n", static_cast<unsigned long long>(dropped));
  return r.failures.empty() && l.count > 0 ? 0 : 1;
}

}  // namespace

void add_bench_live(CLI::App& bench, Action& action) {
  auto args = std::make_shared<BenchLiveArgs>();
  CLI::App* live = bench.add_subcommand(
      "live", "latency (p50/p99/max), CPU per second of data and peak memory of a live run of the simulator");
  live->add_option("--scenario", args->scenario, "simulator scenario (luxloc sim --help)")->capture_default_str();
  live->add_option("--duration", args->duration_s, "seconds of real time")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  live->add_option("--width", args->width, "camera image width, px")->check(CLI::Range(16, 8192))->capture_default_str();
  live->add_option("--height", args->height, "camera image height, px")->check(CLI::Range(16, 8192))->capture_default_str();
  live->add_option("--fps", args->fps, "camera frame rate")->check(CLI::Range(1.0, 240.0))->capture_default_str();
  live->add_option("--imu-rate", args->imu_rate_hz, "IMU rate, Hz")->check(CLI::Range(1.0, 10000.0))->capture_default_str();
  live->add_option("--particles", args->particles, "number of particles (default: run's)")
      ->check(CLI::Range(std::size_t{10}, std::size_t{10'000'000}));
  live->add_option("--threads", args->threads, "worker threads for the filter (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  live->add_option("--mqtt", args->mqtt, "also publish to this MQTT broker (repeatable)")->type_name("HOST:PORT[/TOPIC]");
  live->add_option("--web", args->web, "also serve the live view here")->type_name("[HOST:]PORT");
  live->callback([&action, args] { action = [args] { return run_bench_live(*args); }; });
}

}  // namespace luxloc::app
