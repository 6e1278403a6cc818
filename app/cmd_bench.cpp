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
#include "core/fusion/reprojection_likelihood.hpp"
#include "core/sim/scenario.hpp"
#include "core/vlc/led_class_index.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc::app {
namespace {

struct BenchPfArgs {
  std::size_t particles = 100000;
  int threads = 0;
  int steps = 200;
  std::string filter = "pf";
  bool genetic_as_published = false;  // gpf without GeneticOptions::preserve_spread
  std::uint64_t seed = 1;
  // gaussian: a 5 cm position fix; reprojection: the LEDs in view as known LEDs;
  // association: the same blobs as reused frequency classes, each particle choosing its copy.
  std::string weigh = "gaussian";
  double floor_w = 60.0, pitch = 2.5, ceiling = 3.0;  // the reuse map: floor_w x floor_w / 2
};

// A floor of ceiling LEDs on a grid at `pitch` (m) with 12 frequency classes tiled 4 x 3:
// copies of a class are 4 pitches apart along x and 3 along y (the reuse distance).
LedMap reuse_grid_map(double width, double depth, double pitch, double z) {
  std::vector<Led> leds;
  const int nx = static_cast<int>(std::floor(width / pitch + 1e-9)) + 1;
  const int ny = static_cast<int>(std::floor(depth / pitch + 1e-9)) + 1;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      Led l;
      l.id = static_cast<int>(leds.size()) + 1;
      const int klass = i % 4 + 4 * (j % 3);
      l.freq_hz = 1000.0 * std::pow(1.05, klass);  // 5 % apart: well separable
      l.p_inW = {i * pitch, j * pitch, z};
      leds.push_back(l);
    }
  return LedMap(std::move(leds), "bench reuse grid");
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The tight-coupling weighing on a floor that reuses frequencies: each step predicts, builds
// the frame's ReprojectionLikelihood from the LEDs in view (found with the class index, not
// a loop over the map), weighs every particle with it (association: one turn and one grid
// lookup per particle and term) and resamples.
int run_bench_reprojection(const BenchPfArgs& a, int threads) {
  const bool reuse = a.weigh == "association";
  const double floor_d = 0.5 * a.floor_w;
  const LedMap map = reuse_grid_map(a.floor_w, floor_d, a.pitch, a.ceiling);
  const LedClassIndex index(map);
  const CameraModel camera = sim::default_sim_camera();
  const double z_B = 1.0, sigma_px = 2.0;
  ParticleFilterOptions o;
  o.particles = a.particles;
  o.seed = a.seed;
  o.policy = a.filter == "gpf" ? ResamplingPolicy::Genetic : ResamplingPolicy::Copy;
  o.genetic.preserve_spread = !a.genetic_as_published;
  o.resample_every_correction = true;
  ParticleFilter pf(o);
  const double dt = 0.01, radius = 2.0, omega = 0.5;
  const Eigen::Vector2d centre(0.5 * a.floor_w + 0.3 * a.pitch, 0.5 * floor_d + 0.2 * a.pitch);
  const auto truth = [&](int k) {
    const double t = k * dt;
    return Eigen::Vector2d(centre.x() + radius * std::cos(omega * t), centre.y() + radius * std::sin(omega * t));
  };
  FastRng noise(a.seed + 17);
  // The frame's terms: every LED the camera sees from the true pose (level device), with
  // pixel noise.
  std::vector<int> near;
  const auto terms_at = [&](const Eigen::Vector2d& p) {
    std::vector<ReprojectionTerm> terms;
    near.clear();
    index.within(p.x(), p.y(), 2.0 * (a.ceiling - z_B) + 1.0, near);
    const Eigen::Vector3d p_B(p.x(), p.y(), z_B);
    for (int i : near) {
      const Led& l = map.leds()[static_cast<std::size_t>(i)];
      const Eigen::Vector3d p_LinC = camera.R_CtoB.transpose() * (l.p_inW - p_B) - camera.R_CtoB.transpose() * camera.p_CinB;
      Eigen::Vector2d uv;
      if (!camera.project(p_LinC, uv) || uv.x() < 5 || uv.y() < 5 || uv.x() > camera.width - 5 ||
          uv.y() > camera.height - 5)
        continue;
      uv += sigma_px * Eigen::Vector2d(noise.normal(), noise.normal());
      ReprojectionTerm t{l.p_inW, uv, 1.0 / (sigma_px * sigma_px), -1};
      if (reuse) {
        t.p_LinW.setZero();
        t.klass = map.class_of(static_cast<std::size_t>(i));
      }
      terms.push_back(t);
    }
    return terms;
  };
  pf.initialize(truth(0), Eigen::Matrix2d::Identity() * 0.01);
  using Clock = std::chrono::steady_clock;
  double predict_s = 0.0, correct_s = 0.0, cpu_s = 0.0, best_s = 1e300;
  std::size_t term_count = 0, refused = 0;
  const int warmup = 5;
  for (int k = 1; k <= warmup + a.steps; ++k) {
    const Eigen::Vector2d p = truth(k);
    MotionInput u;
    u.dt = dt;
    u.has_acc = true;
    u.acc_inW = -omega * omega * (p - centre);
    std::vector<ReprojectionTerm> terms = terms_at(p);  // the decoder's output: not timed
    if (k > warmup) term_count += terms.size();
    if (k == warmup + 1) cpu_s = -cpu_seconds();
    const auto t0 = Clock::now();
    pf.predict(u);
    const auto t1 = Clock::now();
    const ReprojectionLikelihood lik(camera, Eigen::Matrix3d::Identity(), z_B, std::move(terms), 5.0 * sigma_px,
                                     ReuseAssociation{&map, &index});
    if (pf.weigh(lik))
      pf.normalize_and_resample();
    else
      ++refused;
    const auto t2 = Clock::now();
    if (k > warmup) {
      predict_s += std::chrono::duration<double>(t1 - t0).count();
      correct_s += std::chrono::duration<double>(t2 - t1).count();
      best_s = std::min(best_s, std::chrono::duration<double>(t2 - t0).count());
    }
  }
  cpu_s += cpu_seconds();
  const PlanarEstimate e = pf.estimate();
  const double err = (e.p - truth(warmup + a.steps)).norm();
  const double step_s = (predict_s + correct_s) / a.steps;
  const double ns_pp = step_s * 1e9 / static_cast<double>(a.particles);
  const double terms_per_frame = static_cast<double>(term_count) / a.steps;
  std::printf("luxloc bench pf: filter %s, %zu particles, %d thread%s, %d steps (each: propagate, weigh with the "
              "reprojection of the LEDs in view%s, normalise, resample)\n",
              a.filter.c_str(), a.particles, threads, threads == 1 ? "" : "s", a.steps,
              reuse ? " as reused frequency classes: per-particle association" : " (known LEDs)");
  std::printf("  map                    %zu LEDs, %zu frequency classes, %.1f m reuse distance, %.2f LEDs in view "
              "per frame\n",
              map.size(), map.classes().size(), map.min_reuse_distance_m(), terms_per_frame);
  std::printf("  time per step          %.4f ms   (propagate %.4f ms, weigh+normalise+resample %.4f ms)\n",
              step_s * 1e3, predict_s * 1e3 / a.steps, correct_s * 1e3 / a.steps);
  std::printf("  fastest step           %.4f ms   (%.2f ns per particle-step; the floor when other load disturbs)\n",
              best_s * 1e3, best_s * 1e9 / static_cast<double>(a.particles));
  std::printf("  ns per particle-step   %.2f\n", ns_pp);
  std::printf("  weighing ns per particle-term  %.2f   (weigh+normalise+resample / particles / LEDs in view)\n",
              terms_per_frame > 0 ? correct_s * 1e9 / a.steps / static_cast<double>(a.particles) / terms_per_frame
                                  : 0.0);
  std::printf("  particle-steps/s       %.3g\n", 1e9 / ns_pp);
  std::printf("  cpu time per step      %.4f ms   (all threads; wall x threads when none waits)\n",
              cpu_s * 1e3 / a.steps);
  std::printf("  final error            %.3f m   (sanity: the filter tracked; %zu frames refused)\n", err, refused);
  return e.valid && std::isfinite(err) ? 0 : 1;
}

int run_bench_pf(const BenchPfArgs& a) {
  std::unique_ptr<tbb::global_control> limit;
  if (a.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(a.threads));
  const auto threads = static_cast<int>(
      std::min<std::size_t>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
                            static_cast<std::size_t>(tbb::this_task_arena::max_concurrency())));
  if (a.weigh != "gaussian") return run_bench_reprojection(a, threads);
  FilterSettings settings;
  settings.name = a.filter;
  settings.pf.genetic.preserve_spread = !a.genetic_as_published;
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
  pf->add_flag("--genetic-as-published", args->genetic_as_published,
               "gpf: the seed's genetic step alone, without restoring the spread it removes");
  pf->add_option("--seed", args->seed, "random seed")->capture_default_str();
  pf->add_option("--weigh", args->weigh,
                 "gaussian (a 5 cm position fix) | reprojection (the LEDs in view, known) | association (the same "
                 "blobs as reused frequency classes: each particle associates its copy)")
      ->check(CLI::IsMember({"gaussian", "reprojection", "association"}))
      ->capture_default_str();
  pf->add_flag_callback(
      "--association", [args] { args->weigh = "association"; }, "same as --weigh association");
  pf->add_option("--floor", args->floor_w, "reuse map: floor width (m); depth is half of it")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  pf->add_option("--pitch", args->pitch, "reuse map: LED grid pitch (m)")->check(CLI::Range(0.5, 100.0))->capture_default_str();
  pf->add_option("--ceiling", args->ceiling, "reuse map: ceiling height (m; the device is at 1 m)")
      ->check(CLI::Range(1.5, 50.0))
      ->capture_default_str();
  pf->callback([&action, args] { action = [args] { return run_bench_pf(*args); }; });
  add_bench_soak(*bench, action);
  add_bench_live(*bench, action);
}

}  // namespace luxloc::app
