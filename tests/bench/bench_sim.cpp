// Simulator micro-benchmarks: one rolling-shutter frame, and its PNG encoding as the session writer does it.
#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "core/sim/simulator.hpp"

namespace {

const luxloc::sim::Simulator& walk() {
  static const luxloc::sim::Simulator sim(luxloc::sim::make_scenario("walk"), luxloc::sim::SimOptions{});
  return sim;
}

void BM_RenderWalkFrame(benchmark::State& state) {
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(walk().render(k).gray.data);
    k = (k + 7) % walk().frame_count();
  }
}
BENCHMARK(BM_RenderWalkFrame)->Unit(benchmark::kMillisecond);

void BM_EncodeWalkFramePng(benchmark::State& state) {
  const cv::Mat gray = walk().render(300).gray;
  std::vector<uchar> buf;
  for (auto _ : state) {
    cv::imencode(".png", gray, buf,
                 {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY});
    benchmark::DoNotOptimize(buf.data());
  }
  state.counters["bytes"] = static_cast<double>(buf.size());
}
BENCHMARK(BM_EncodeWalkFramePng)->Unit(benchmark::kMillisecond);

}  // namespace
