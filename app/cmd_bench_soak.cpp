// `luxloc bench soak`: the soak test of issue 13 — a long stretch of simulated live input
// (the sim: source, faster than real time: as fast as the fusion takes it) through the
// whole `run` path (sources, queues, fusion, outputs), printing the resident memory (RSS),
// the queue depths and the time samples wait in their queue as the run goes on, then
// whether the RSS stayed flat after the first minute (growth <= 5 %). Figures in
// docs/RELIABILITY.md "Soak".
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "app/run_session.hpp"

namespace luxloc::app {
namespace {

struct SoakArgs {
  double duration_s = 3600.0;
  double every_s = 60.0;
  std::string scenario = "walk";
  std::string out = "/dev/null";
  std::uint64_t seed = 1;
  std::size_t particles = 0;  // 0: run's default
};

// The C library heap's bytes in live allocations (mallinfo2: arenas' in-use chunks plus
// mmapped ones), MB: separates memory the program holds from pages the heap keeps free.
double heap_in_use_mb() {
  const struct mallinfo2 m = ::mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

double rss_mb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// 5 %: the limit for "flat"; the first minute (buffers, caches, the filter's arrays
// growing to their working size) is the baseline, not part of the check.
constexpr double kFlatLimit = 0.05;
constexpr double kWarmupS = 60.0;
constexpr double kMiB = 1024.0 * 1024.0;
// What is judged flat is the floor of the RSS: its lowest value in each printed interval
// (sampled at every pipeline probe, every 1024 fused samples). Camera frames waiting in the
// source queues are memory in use, by design, up to the pipeline's per-source budget
// (PipelineOptions::source_queue_bytes, 16 MiB), whenever the fusion falls behind (a loaded
// machine, a re-initialisation); the RSS rises by them in a backlog and falls back within
// seconds once it drains and the heap is trimmed (docs/RELIABILITY.md "Soak"). A leak lifts
// the floor. The baseline is the floor of the first interval after the first minute; every
// later floor must stay within 5 % of it, and every peak within it plus the frame budget.

int run_soak(const SoakArgs& a) {
  RunConfig cfg;
  char spec[160];
  std::snprintf(spec, sizeof spec, "sim:%s,realtime=0,duration=%g,seed=%llu", a.scenario.c_str(), a.duration_s,
                static_cast<unsigned long long>(a.seed));
  cfg.sources = {spec};
  cfg.out = a.out;
  cfg.status = "off";
  if (a.particles > 0) cfg.fusion.pf.particles = a.particles;
  std::printf("luxloc bench soak: %s, poses to %s; a line every %g s of data\n", spec, a.out.c_str(), a.every_s);
  std::printf("%9s %8s %7s %8s %8s %8s %8s %10s %10s %10s %10s\n", "data_s", "wall_s", "x_rt", "rss_MB", "floor_MB",
              "peak_MB", "heap_MB", "frames_MB", "max_queue", "max_poses", "max_wait_ms");
  std::fflush(stdout);

  const auto wall0 = std::chrono::steady_clock::now();
  bool have_t0 = false;
  TimeNs t0 = 0;
  double next_line = a.every_s, last_wall = 0.0, last_data = 0.0;
  std::size_t max_queue = 0, max_poses = 0;
  double max_wait = 0.0, rss_last = 0.0;
  // This interval's lowest and highest RSS and most queued frame pixels (MB).
  double floor_iv = std::numeric_limits<double>::infinity(), peak_iv = 0.0, frames_iv = 0.0;
  double baseline = 0.0, floor_max_after = 0.0, peak_max_after = 0.0;
  cfg.probe = [&](const PipelineProbe& p) {
    if (!have_t0) {
      have_t0 = true;
      t0 = p.t;
    }
    for (std::size_t d : p.source_depths) max_queue = std::max(max_queue, d);
    max_poses = std::max(max_poses, p.pose_depth);
    max_wait = std::max(max_wait, p.queue_wait_s);
    const double rss = rss_mb();
    rss_last = rss;
    floor_iv = std::min(floor_iv, rss);
    peak_iv = std::max(peak_iv, rss);
    frames_iv = std::max(frames_iv, static_cast<double>(p.queued_frame_bytes) / kMiB);
    const double data = ns_to_seconds(p.t - t0);
    if (data < next_line) return;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double interval_start = next_line - a.every_s;
    if (interval_start >= kWarmupS && baseline == 0.0) {
      baseline = floor_iv;
    } else if (baseline > 0.0) {
      floor_max_after = std::max(floor_max_after, floor_iv);
      peak_max_after = std::max(peak_max_after, peak_iv);
    }
    std::printf("%9.0f %8.1f %7.1f %8.1f %8.1f %8.1f %8.1f %10.1f %10zu %10zu %10.2f\n", data, wall,
                wall > last_wall ? (data - last_data) / (wall - last_wall) : 0.0, rss, floor_iv, peak_iv,
                heap_in_use_mb(), frames_iv, max_queue, max_poses, max_wait * 1e3);
    std::fflush(stdout);
    last_wall = wall;
    last_data = data;
    max_queue = max_poses = 0;
    max_wait = 0.0;
    floor_iv = std::numeric_limits<double>::infinity();
    peak_iv = frames_iv = 0.0;
    next_line += a.every_s;
  };
  const RunOutcome r = run_session(cfg, std::cerr);
  if (baseline > 0.0 && floor_max_after > 0.0) {
    const double growth = floor_max_after / baseline - 1.0;
    const double budget = static_cast<double>(PipelineOptions{}.source_queue_bytes) / kMiB;
    const double ceiling = (baseline + budget) * (1.0 + kFlatLimit);
    const bool flat = growth <= kFlatLimit, bounded = peak_max_after <= ceiling;
    std::printf("rss floor after the first minute %.1f MB, highest floor later %.1f MB: growth %+.1f %% (%s, limit "
                "%.0f %%)\n",
                baseline, floor_max_after, growth * 100.0, flat ? "flat" : "GROWS", kFlatLimit * 100.0);
    std::printf("rss peak later %.1f MB, at the end %.1f MB: %s the floor plus the %.0f MiB frame budget (+%.0f %%: "
                "%.1f MB)\n",
                peak_max_after, rss_last, bounded ? "within" : "ABOVE", budget, kFlatLimit * 100.0, ceiling);
    if (!flat || !bounded) return 1;
  } else {
    std::printf("run too short for a floor after the first minute (two intervals past it): no RSS growth figure\n");
  }
  return r.failures.empty() ? 0 : 1;
}

}  // namespace

void add_bench_soak(CLI::App& bench, Action& action) {
  auto a = std::make_shared<SoakArgs>();
  CLI::App* soak = bench.add_subcommand(
      "soak", "simulated live input at full speed through the whole run path: RSS, queue depths and queue wait over time");
  soak->add_option("--duration", a->duration_s, "seconds of simulated input")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  soak->add_option("--every", a->every_s, "print a line every this many seconds of data")
      ->check(CLI::Range(0.1, 1e6))
      ->capture_default_str();
  soak->add_option("--scenario", a->scenario, "sim scenario (walk: IMU + camera frames; uwb: IMU + UWB)")
      ->capture_default_str();
  soak->add_option("--out", a->out, "pose file")->capture_default_str();
  soak->add_option("--seed", a->seed, "simulator seed")->capture_default_str();
  soak->add_option("--particles", a->particles, "particles (0: run's default)")->capture_default_str();
  soak->callback([&action, a] { action = [a] { return run_soak(*a); }; });
}

}  // namespace luxloc::app
