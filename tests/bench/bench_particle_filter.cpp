// One full particle-filter step — propagate, weigh with a Gaussian position fix,
// normalise, resample — at 1k .. 1M particles, one thread and all cores (issue #5).
// Run: build/tests/luxloc_bench --benchmark_filter=ParticleFilter
// items_per_second is particle-steps per second.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>

#include "core/filter/fast_rng.hpp"
#include "core/filter/filter_factory.hpp"

namespace {

using namespace luxloc;

void run_steps(benchmark::State& state, const std::string& filter) {
  const auto particles = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));  // 0: all cores
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(threads));
  FilterSettings s{filter};
  s.pf.particles = particles;
  s.pf.resample_every_correction = true;  // every step includes a resampling
  auto f = make_planar_filter(s);
  FastRng noise(17);
  const double dt = 0.01, omega = 0.5, radius = 2.0, sigma = 0.05;
  f->initialize({radius, 0.0}, Eigen::Matrix2d::Identity() * 0.01);
  int k = 0;
  for (auto _ : state) {
    ++k;
    const Eigen::Vector2d p(radius * std::cos(omega * k * dt), radius * std::sin(omega * k * dt));
    f->predict(MotionInput{dt, -omega * omega * p, true});
    PositionMeasurement m;
    m.z = p + sigma * Eigen::Vector2d(noise.normal(), noise.normal());
    m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
    f->correct(m);
    benchmark::DoNotOptimize(f->estimate());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(particles));
  state.counters["per_particle_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(particles),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}

void BM_ParticleFilterStep(benchmark::State& state) { run_steps(state, "pf"); }
void BM_GeneticParticleFilterStep(benchmark::State& state) { run_steps(state, "gpf"); }

void particle_counts(benchmark::internal::Benchmark* b) {
  for (int n : {1000, 10000, 100000, 1000000})
    for (int t : {1, 0}) b->Args({n, t});
  b->ArgNames({"particles", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_ParticleFilterStep)->Apply(particle_counts);
BENCHMARK(BM_GeneticParticleFilterStep)->Apply(particle_counts);
