// Stripe decoder micro-benchmarks: one 640x480 rolling-shutter frame with 4 LEDs in view,
// decoded on one core (OpenCV's own threads off). Target: <= 3 ms per frame.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/sim/frame_renderer.hpp"
#include "core/vlc/stripe_decoder.hpp"

namespace {

using namespace luxloc;

struct Scene {
  CameraModel camera;
  LedMap map;
  cv::Mat frame;
  std::size_t leds_in_view = 0;
};

// Four LEDs of a 2 x 2 grid (1.2 m apart, 3 m high) seen from 1.2 m below their middle,
// 0.2 m discs (about 51 px across, all inside), 1.5 to 3.5 kHz, 100 us exposure, 30 us per row.
const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    sc.camera.fx = sc.camera.fy = 460;
    sc.camera.row_time_s = 30e-6;
    sc.camera.exposure_s = 100e-6;
    sc.camera.R_CtoB << 0, 1, 0, -1, 0, 0, 0, 0, 1;
    std::vector<Led> leds;
    const double f[] = {1500, 2000, 2700, 3500};
    for (int i = 0; i < 4; ++i) {
      Led l;
      l.id = i + 1;
      l.freq_hz = f[i];
      l.p_inW = Eigen::Vector3d(1.2 * (i % 2), 1.2 * (i / 2), 3.0);
      l.diameter_m = 0.2;
      leds.push_back(l);
    }
    sc.map = LedMap(leds, "bench");
    const sim::PoseAt pose = [](double) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T.translation() = Eigen::Vector3d(0.6, 0.6, 1.2);
      return T;
    };
    std::mt19937_64 rng(1);
    const sim::RenderedFrame fr = sim::render_frame(sc.camera, sc.map, pose, 0.0, sim::RenderOptions{}, rng,
                                                    {0.1, 0.4, 0.7, 0.2});
    sc.frame = fr.gray;
    sc.leds_in_view = fr.leds.size();
    return sc;
  }();
  return s;
}

void BM_DecodeFrame640x480FourLeds(benchmark::State& state) {
  cv::setNumThreads(0);  // one core: no OpenCV worker threads
  const Scene& s = scene();
  const StripeDecoder decoder(s.camera, s.map);
  std::size_t accepted = 0;
  for (auto _ : state) {
    const auto obs = decoder.decode(s.frame);
    accepted = 0;
    for (const auto& o : obs) accepted += o.accepted() ? 1 : 0;
    benchmark::DoNotOptimize(obs.data());
  }
  state.counters["leds_in_view"] = static_cast<double>(s.leds_in_view);
  state.counters["accepted"] = static_cast<double>(accepted);
}
BENCHMARK(BM_DecodeFrame640x480FourLeds)->Unit(benchmark::kMillisecond);

void BM_DecodeDarkFrame640x480(benchmark::State& state) {
  cv::setNumThreads(0);
  const Scene& s = scene();
  const StripeDecoder decoder(s.camera, s.map);
  cv::Mat dark(480, 640, CV_8UC1);
  cv::randn(dark, 6.0, 1.2);
  for (auto _ : state) benchmark::DoNotOptimize(decoder.decode(dark).data());
}
BENCHMARK(BM_DecodeDarkFrame640x480)->Unit(benchmark::kMillisecond);

}  // namespace
