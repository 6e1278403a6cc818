// The walker population of `luxloc sim --walker random` (issue 12 part 1): per-seed draws
// within the documented ranges, reproducible, and applied to the scenario's walk.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/sim/scenario.hpp"
#include "core/sim/walker_population.hpp"

using namespace luxloc::sim;

TEST_CASE("draw_walker: ranges of issue 12, reproducible per seed, different across seeds", "[sim][walker]") {
  std::set<long> lengths;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const WalkerDraw w = draw_walker(seed, 90.0);
    INFO("seed " << seed);
    CHECK(w.step_hz >= 1.4);
    CHECK(w.step_hz <= 2.2);
    CHECK(w.step_length_m >= 0.35 - 1e-12);
    CHECK(w.step_length_m <= 0.85);
    CHECK(w.speed_mps <= 1.8);
    CHECK(w.speed_mps == Approx(w.step_length_m * w.step_hz));
    CHECK(w.corner_sigma_m >= 0.3);
    CHECK(w.corner_sigma_m <= 1.0);
    REQUIRE_FALSE(w.walking.empty());
    CHECK(w.walking.front().start_s == 2.0);
    CHECK(std::isinf(w.walking.back().stop_s));
    for (std::size_t i = 1; i < w.walking.size(); ++i) {
      const double stop = w.walking[i].start_s - w.walking[i - 1].stop_s;
      CHECK(stop >= 1.0);
      CHECK(stop <= 10.0);
    }
    lengths.insert(std::lround(w.step_length_m * 100));
    const WalkerDraw again = draw_walker(seed, 90.0);
    CHECK(again.step_length_m == w.step_length_m);
    CHECK(again.walking.size() == w.walking.size());
  }
  CHECK(lengths.size() > 30);  // the seeds spread over the range
}

TEST_CASE("apply_walker walks the scenario's path with the drawn gait", "[sim][walker]") {
  const Scenario s = make_scenario("walk");
  REQUIRE(s.walk);
  const WalkerDraw w = draw_walker(7, 90.0);
  const WalkOptions o = apply_walker(*s.walk, w);
  CHECK(o.waypoints == s.walk->waypoints);
  CHECK(o.gait.speed_mps == w.speed_mps);
  CHECK(o.gait.step_hz == w.step_hz);
  CHECK(o.corner_sigma_m == w.corner_sigma_m);
  const WalkTrajectory t(o);
  // Heel strikes at the drawn cadence while walking (away from the stops' ramps).
  const auto strikes = t.step_times(90.0);
  REQUIRE(strikes.size() > 20);
  const double mid = 0.5 * (w.walking.front().start_s + w.walking.front().stop_s);
  std::size_t k = 0;
  while (k + 1 < strikes.size() && strikes[k] < mid) ++k;
  CHECK(strikes[k] - strikes[k - 1] == Approx(1.0 / w.step_hz).epsilon(0.02));
  CHECK_FALSE(make_scenario("static").walk);  // nothing to replace there
}
