// Per-frame VLC fusion cost against the map's size (issue 14: "per-frame fusion cost with
// 10 LEDs and with 5000 LEDs in the map within 10 % of each other"): the same camera frame
// (four LEDs of reused frequency classes in view) fused against a 10-LED map and against a
// 5000-LED map (100 x 50 grid, 2 m pitch, 12 classes tiled 4 x 3) that holds those LEDs at
// the same places. The 10-LED map is the 2 x 5 block of the big one over the device, so
// the four LEDs in view have a copy each 6 m away in both maps: the same classes, the same
// capture radius, the same association work; only the map's size differs.
//
// BM_VlcFrameFusion: decode the frame (VlcFrontend::decode: stripes -> frequency class),
//   build the frame's ReprojectionLikelihood, weigh N particles (each associates its copy
//   of every reused class) and resample: the fusion engine's tight-coupling correction.
// BM_VlcWeigh: the same without the decoding: weigh and resample (the per-particle part).
// Counters: leds_in_view (decoded), map_bytes (LedMap), index_bytes (LedClassIndex).
// Run: build/tests/luxloc_bench --benchmark_filter='Vlc(FrameFusion|Weigh)'
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <string>

#include "core/filter/particle_filter.hpp"
#include "core/fusion/fusion_options.hpp"
#include "core/fusion/vlc_frontend.hpp"
#include "core/sim/frame_renderer.hpp"
#include "core/sim/scenario.hpp"
#include "core/vlc/led_class_index.hpp"

namespace {

using namespace luxloc;

constexpr double kPitch = 2.0, kCeiling = 4.0, kDeviceZ = 1.0;  // 3 m up: the 2 x 2 LEDs fit the 640 x 480 view

Led grid_led(int i, int j) {
  Led l;
  l.id = j * 100 + i + 1;
  l.freq_hz = 1000.0 + 300.0 * ((i % 4) + 4 * (j % 3));
  l.p_inW = {kPitch * i, kPitch * j, kCeiling};
  l.diameter_m = 0.3;
  return l;
}

// The device under the middle of LEDs (40, 20), (41, 20), (40, 21), (41, 21).
const Eigen::Vector3d& device() {
  static const Eigen::Vector3d p(kPitch * 40.5 + 0.1, kPitch * 20.5 - 0.05, kDeviceZ);
  return p;
}

LedMap make_map(int leds) {
  std::vector<Led> v;
  if (leds >= 5000) {
    for (int j = 0; j < 50; ++j)
      for (int i = 0; i < 100; ++i) v.push_back(grid_led(i, j));
  } else {
    for (int j = 20; j < 25; ++j)
      for (int i = 40; i < 42; ++i) v.push_back(grid_led(i, j));
  }
  return LedMap(std::move(v), "bench map");
}

std::size_t map_bytes(const LedMap& m) {
  std::size_t n = sizeof(LedMap) + m.leds().capacity() * sizeof(Led) + m.size() * sizeof(int);
  for (const FrequencyClass& c : m.classes()) n += sizeof(FrequencyClass) + c.members.capacity() * sizeof(int);
  return n;
}

struct Setup {
  explicit Setup(int leds)
      : camera(sim::default_sim_camera()), map(make_map(leds)), index(map), frontend(camera, map, FusionOptions{}, kDeviceZ) {
    std::mt19937_64 rng(7);
    const auto pose = [](double) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = device();
      return T;
    };
    frame.t = 1'000'000'000;
    // Rendering loops over the whole map: set-up only, not timed.
    const sim::RenderedFrame r = sim::render_frame(camera, map, pose, 1.0, sim::RenderOptions{}, rng);
    frame.gray = r.gray;
    rendered = 0;
    for (const sim::RenderedLed& l : r.leds) rendered += l.fully_inside;
    decoded = frontend.decode(frame);
  }
  CameraModel camera;
  LedMap map;
  LedClassIndex index;  // the size figure (the frontend holds its own)
  VlcFrontend frontend;
  FrameSample frame;
  DecodedFrame decoded;
  int rendered = 0;  // LEDs fully inside the frame
};

const Setup& setup(int leds) {
  static std::unique_ptr<Setup> small, big;
  std::unique_ptr<Setup>& s = leds >= 5000 ? big : small;
  if (!s) s = std::make_unique<Setup>(leds);
  return *s;
}

ParticleFilter make_filter(std::size_t n) {
  ParticleFilterOptions o;
  o.particles = n;
  o.resample_every_correction = true;
  ParticleFilter pf(o);
  pf.initialize(device().head<2>(), Eigen::Matrix2d::Identity() * 0.01);
  return pf;
}

void counters(benchmark::State& state, const Setup& s) {
  state.counters["leds_in_view"] = s.decoded.leds;
  state.counters["map_bytes"] = static_cast<double>(map_bytes(s.map));
  state.counters["index_bytes"] = static_cast<double>(s.index.memory_bytes());
}

void BM_VlcFrameFusion(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  if (s.decoded.leds < 4) {
    state.SkipWithError(("the frame's four LEDs were not decoded: " + std::to_string(s.decoded.leds) + " of " +
                         std::to_string(s.rendered) + " rendered, " + std::to_string(s.decoded.rejected) + " refused")
                            .c_str());
    return;
  }
  ParticleFilter pf = make_filter(static_cast<std::size_t>(state.range(1)));
  for (auto _ : state) {
    const DecodedFrame d = s.frontend.decode(s.frame);
    const ReprojectionLikelihood lik = s.frontend.likelihood(d, Eigen::Matrix3d::Identity());
    if (pf.weigh(lik)) pf.normalize_and_resample();
    benchmark::DoNotOptimize(pf.estimate());
  }
  counters(state, s);
}

void BM_VlcWeigh(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  if (s.decoded.leds < 4) {
    state.SkipWithError(("the frame's four LEDs were not decoded: " + std::to_string(s.decoded.leds) + " of " +
                         std::to_string(s.rendered) + " rendered, " + std::to_string(s.decoded.rejected) + " refused")
                            .c_str());
    return;
  }
  ParticleFilter pf = make_filter(static_cast<std::size_t>(state.range(1)));
  const ReprojectionLikelihood lik = s.frontend.likelihood(s.decoded, Eigen::Matrix3d::Identity());
  for (auto _ : state) {
    if (pf.weigh(lik)) pf.normalize_and_resample();
    benchmark::DoNotOptimize(pf.estimate());
  }
  state.SetItemsProcessed(state.iterations() * state.range(1));
  counters(state, s);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int n : {2000, 100000})
    for (int leds : {10, 5000}) b->Args({leds, n});
  b->ArgNames({"leds", "particles"})->UseRealTime()->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK(BM_VlcFrameFusion)->Apply(sizes);
BENCHMARK(BM_VlcWeigh)->Apply(sizes);
