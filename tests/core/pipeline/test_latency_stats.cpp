// Latency summaries: the run's histogram (fixed memory, 2 % bins) and the live window.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/pipeline/latency_stats.hpp"

using namespace luxloc;

TEST_CASE("The latency histogram gives p50, p99 and max within its 2 % bins", "[pipeline]") {
  LatencyHistogram h;
  CHECK(std::isnan(h.summary().p50_s));
  for (int i = 1; i <= 1000; ++i) h.add(1e-3 * i / 100.0);  // 10 us .. 10 ms, uniform
  h.add(std::nan(""));  // ignored
  const LatencySummary s = h.summary();
  CHECK(s.count == 1000);
  CHECK(s.p50_s == Approx(5e-3).epsilon(0.03));
  CHECK(s.p99_s == Approx(9.9e-3).epsilon(0.03));
  CHECK(s.max_s == Approx(10e-3));
  LatencyHistogram huge;
  huge.add(1e3);  // beyond the last bin: still counted, max exact
  CHECK(huge.summary().max_s == 1e3);
  CHECK(huge.summary().p50_s <= 1e3);
}

TEST_CASE("The latency window keeps the last values and gives exact percentiles", "[pipeline]") {
  LatencyWindow w(100);
  for (int i = 0; i < 1000; ++i) w.add(1.0);  // old values, pushed out
  for (int i = 1; i <= 100; ++i) w.add(1e-3 * i);
  const LatencySummary s = w.summary();
  CHECK(s.count == 100);
  CHECK(s.p50_s == Approx(50e-3));
  CHECK(s.p99_s == Approx(99e-3));
  CHECK(s.max_s == Approx(100e-3));
}
