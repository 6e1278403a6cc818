// `luxloc bench pf`: times one full particle-filter step — propagate, weigh with a
// Gaussian position fix, normalise, resample — on a synthetic walk (issue #5's benchmark;
// tests/bench/bench_particle_filter.cpp is the Google Benchmark version).
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "core/filter/fast_rng.hpp"
#include "core/filter/filter_factory.hpp"

namespace luxloc::app {
namespace {

struct BenchPfArgs {
  std::size_t particles = 100000;
  int threads = 0;
  int steps = 200;
  std::string filter = "pf";
  std::uint64_t seed = 1;
};

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int run_bench_pf(const BenchPfArgs& a) {
  std::unique_ptr<tbb::global_control> limit;
  if (a.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(a.threads));
  const auto threads = static_cast<int>(
      std::min<std::size_t>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
                            static_cast<std::size_t>(tbb::this_task_arena::max_concurrency())));
  FilterSettings settings;
  settings.name = a.filter;
  settings.pf.particles = a.particles;
  settings.pf.seed = a.seed;
  settings.pf.resample_every_correction = true;  // every step includes a resampling
  const std::unique_ptr<PlanarFilter> filter = make_planar_filter(settings);

  // A device walking a 2 m circle at 1 m/s, 100 Hz steps, a 5 cm fix at every step.
  const double dt = 0.01, radius = 2.0, omega = 0.5, sigma = 0.05;
  FastRng noise(a.seed + 17);
  const auto truth = [&](int k) {
    const double t = k * dt;
    return Eigen::Vector2d(radius * std::cos(omega * t), radius * std::sin(omega * t));
  };
  filter->initialize(truth(0), Eigen::Matrix2d::Identity() * 0.01);
  using Clock = std::chrono::steady_clock;
  double predict_s = 0.0, correct_s = 0.0, cpu_s = 0.0, best_s = 1e300;
  const int warmup = 5;
  for (int k = 1; k <= warmup + a.steps; ++k) {
    const Eigen::Vector2d p = truth(k);
    MotionInput u;
    u.dt = dt;
    u.has_acc = true;
    u.acc_inW = -omega * omega * p;  // centripetal acceleration of the circle
    PositionMeasurement m;
    m.z = p + sigma * Eigen::Vector2d(noise.normal(), noise.normal());
    m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
    if (k == warmup + 1) cpu_s = -cpu_seconds();  // process CPU time over the timed steps
    const auto t0 = Clock::now();
    filter->predict(u);
    const auto t1 = Clock::now();
    filter->correct(m);
    const auto t2 = Clock::now();
    if (k > warmup) {
      predict_s += std::chrono::duration<double>(t1 - t0).count();
      correct_s += std::chrono::duration<double>(t2 - t1).count();
      best_s = std::min(best_s, std::chrono::duration<double>(t2 - t0).count());
    }
  }
  cpu_s += cpu_seconds();
  const PlanarEstimate e = filter->estimate();
  const double err = (e.p - truth(warmup + a.steps)).norm();
  const double step_s = (predict_s + correct_s) / a.steps;
  const double ns_pp = step_s * 1e9 / static_cast<double>(a.particles);
  std::printf("luxloc bench pf: filter %s, %zu particles, %d thread%s, %d steps (each: propagate, weigh a %.0f cm "
              "Gaussian fix, normalise, resample)\n",
              a.filter.c_str(), a.particles, threads, threads == 1 ? "" : "s", a.steps, sigma * 100);
  std::printf("  time per step          %.4f ms   (propagate %.4f ms, weigh+normalise+resample %.4f ms)\n",
              step_s * 1e3, predict_s * 1e3 / a.steps, correct_s * 1e3 / a.steps);
  std::printf("  fastest step           %.4f ms   (%.2f ns per particle-step; the floor when other load disturbs)\n",
              best_s * 1e3, best_s * 1e9 / static_cast<double>(a.particles));
  std::printf("  ns per particle-step   %.2f\n", ns_pp);
  std::printf("  particle-steps/s       %.3g\n", 1e9 / ns_pp);
  std::printf("  cpu time per step      %.4f ms   (all threads; wall x threads when none waits)\n",
              cpu_s * 1e3 / a.steps);
  std::printf("  final error            %.3f m   (sanity: the filter tracked)\n", err);
  return e.valid && std::isfinite(err) ? 0 : 1;
}

}  // namespace

void add_bench_command(CLI::App& root, Action& action) {
  CLI::App* bench = root.add_subcommand("bench", "micro-benchmarks (not run in CI)");
  bench->require_subcommand(1);
  auto args = std::make_shared<BenchPfArgs>();
  CLI::App* pf = bench->add_subcommand(
      "pf", "time one particle-filter step (propagate + weigh + normalise + resample) per particle");
  pf->add_option("--particles", args->particles, "number of particles")
      ->check(CLI::Range(std::size_t{10}, std::size_t{100'000'000}))
      ->capture_default_str();
  pf->add_option("--threads", args->threads, "TBB worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  pf->add_option("--steps", args->steps, "timed steps (after 5 warm-up steps)")
      ->check(CLI::Range(1, 1'000'000))
      ->capture_default_str();
  pf->add_option("--filter", args->filter, "pf (SIR, systematic) | gpf (genetic resampling)")
      ->check(CLI::IsMember({"pf", "gpf"}))
      ->capture_default_str();
  pf->add_option("--seed", args->seed, "random seed")->capture_default_str();
  pf->callback([&action, args] { action = [args] { return run_bench_pf(*args); }; });
  add_bench_soak(*bench, action);
  add_bench_live(*bench, action);
}

}  // namespace luxloc::app
