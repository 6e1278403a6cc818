// The pace drifting within a walk (core/sim/pace_drift.*): the tabulated step count and
// walked distance against closed forms, and their derivatives against finite differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/sim/pace_drift.hpp"

using namespace luxloc::sim;

TEST_CASE("PaceDrift without waves is the steady walk's closed form", "[sim][pace]") {
  const double f0 = 1.8, m = 0.1, k = 2.0 * std::numbers::pi * f0;
  const PaceDrift steady({}, f0, m, 100.0);
  for (double G = 0.0; G < 100.0; G += 3.37) {
    INFO("G " << G);
    CHECK(steady.steps(G) == Approx(f0 * G).margin(1e-10));
    const Jet D = steady.distance(G);
    CHECK(D.v == Approx(G + m * std::sin(k * G) / k).margin(1e-10));
    CHECK(D.d == Approx(1.0 + m * std::cos(k * G)).margin(1e-12));
  }
}

TEST_CASE("PaceDrift: the speed follows its waves, cadence and step length share it", "[sim][pace]") {
  const double f0 = 2.0, m = 0.15;
  const PaceDrift drift({{0.12, 40.0, 0.3}, {0.10, 150.0, 2.0}}, f0, m, 300.0);
  for (double G = 0.5; G < 299.0; G += 7.13) {
    INFO("G " << G);
    const Jet q = drift.speed_factor(G), c = drift.cadence_factor(G), l = drift.length_factor(G);
    CHECK(q.v == Approx(1.0 + 0.12 * std::sin(2 * std::numbers::pi * G / 40.0 + 0.3) +
                        0.10 * std::sin(2 * std::numbers::pi * G / 150.0 + 2.0)));
    CHECK(c.v * l.v == Approx(q.v));  // cadence x step length = speed
    // Derivatives against central differences.
    const double h = 1e-3;
    CHECK(drift.steps(G + h) - drift.steps(G - h) == Approx(2 * h * f0 * c.v).epsilon(1e-7));
    CHECK((drift.cadence_factor(G + h).v - drift.cadence_factor(G - h).v) / (2 * h) == Approx(c.d).margin(1e-8));
    CHECK((drift.cadence_factor(G + h).d - drift.cadence_factor(G - h).d) / (2 * h) == Approx(c.dd).margin(1e-8));
    const Jet D = drift.distance(G);
    CHECK((drift.distance(G + h).v - drift.distance(G - h).v) / (2 * h) == Approx(D.d).margin(1e-6));
    CHECK((drift.distance(G + h).d - drift.distance(G - h).d) / (2 * h) == Approx(D.dd).margin(1e-4));
  }
  // Over whole periods of both waves (600 s covers 40 and 150) the mean speed is the nominal
  // one to within the per-step modulation's last part step.
  const PaceDrift long_drift({{0.12, 40.0, 0.3}, {0.10, 150.0, 2.0}}, f0, 0.0, 600.0);
  CHECK(long_drift.distance(600.0).v == Approx(600.0).margin(1e-8));
}

TEST_CASE("PaceDrift refuses waves that would stop the walker, and time past its tables", "[sim][pace]") {
  CHECK_THROWS_AS(PaceDrift({{0.3, 60.0, 0.0}, {0.25, 100.0, 0.0}}, 1.8, 0.1, 100.0), std::invalid_argument);
  CHECK_THROWS_AS(PaceDrift({{0.1, 1.0, 0.0}}, 1.8, 0.1, 100.0), std::invalid_argument);  // faster than steps
  CHECK_THROWS_AS(PaceDrift({{0.1, 60.0, 0.0}}, 1.8, 0.1, -1.0), std::invalid_argument);
  const PaceDrift d({{0.1, 60.0, 0.0}}, 1.8, 0.1, 50.0);
  CHECK_NOTHROW(d.distance(50.0));
  CHECK_THROWS_AS(d.steps(60.0), std::out_of_range);
  CHECK_THROWS_AS(d.distance(-1.0), std::out_of_range);
}
