// Frequency planning (issue 14): the band a camera separates, the colouring of a floor's
// LEDs, and an independent check of the result: many sampled poses (position, yaw, tilt),
// every LED projected through the camera model, never two of one class in one image.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>

#include "co_visibility_check.hpp"
#include "core/sim/scenario.hpp"
#include "core/vlc/frequency_plan.hpp"
#include "core/vlc/led_visibility.hpp"

using namespace luxloc;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Eigen::Vector2d> grid(int nx, int ny, double s) {
  std::vector<Eigen::Vector2d> p;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) p.emplace_back(1.25 + s * x, 1.25 + s * y);
  return p;
}

// The independent check (tests/co_visibility_check.hpp) for floor-plane positions under a
// flat ceiling.
int views_with_two_of_a_class(const std::vector<Eigen::Vector2d>& p, const std::vector<int>& klass,
                              const CameraModel& cam, double ceiling_z, double device_z, double max_tilt,
                              int samples, std::uint64_t seed) {
  std::vector<Eigen::Vector3d> p3;
  for (const auto& q : p) p3.emplace_back(q.x(), q.y(), ceiling_z);
  return test::views_with_two_of_a_class(p3, klass, cam, device_z, max_tilt, samples, seed);
}

}  // namespace

TEST_CASE("Frequency band: contrast at the exposure caps the top, stripes across a far blob the bottom", "[vlc][plan]") {
  const CameraModel cam = sim::default_sim_camera();  // 100 us exposure, 30 us rows, f 460 px
  const FrequencyBand b = frequency_band(cam, 2.0, 0.2);
  // |sinc(f T)| = 0.5 at f T = 0.6034: 6.03 kHz at 100 us; the row limit 1/(4 x 30 us) is 8.3 kHz.
  CHECK(b.f_max_hz == Approx(6034).epsilon(0.002));
  CHECK(b.high_limit == "contrast");
  CHECK(b.f_min_hz > 1000.0);
  CHECK(b.f_min_hz < 3000.0);
  CHECK(b.capacity >= 12);
  const auto f = spread_frequencies(b, 12);
  REQUIRE(f.size() == 12);
  CHECK(f.front() == Approx(b.f_min_hz));
  CHECK(f.back() == Approx(b.f_max_hz));
  for (std::size_t i = 1; i < f.size(); ++i) CHECK(f[i] / f[i - 1] - 1.0 >= b.relative_step);
  // A longer exposure narrows the band from the top (FIELD_NOTES: 300 us -> about 2 kHz).
  CameraModel slow = cam;
  slow.exposure_s = 300e-6;
  CHECK(frequency_band(slow, 2.0, 0.2).f_max_hz == Approx(2011).epsilon(0.002));
}

TEST_CASE("Frequency plan: a 60 m x 30 m grid in 12 classes, valid from every sampled pose, and not periodic",
          "[vlc][plan]") {
  const CameraModel cam = sim::default_sim_camera();
  const double max_tilt = 15.0 * kPi / 180.0;
  const double conflict = co_visibility_distance_m(cam, 2.0, max_tilt) + 0.2 + 0.25;
  const auto p = grid(24, 12, 2.5);  // 288 LEDs
  FrequencyPlanOptions o;
  o.classes = 12;
  const FrequencyPlan plan = plan_frequency_classes(p, conflict, o);
  REQUIRE(plan.class_of.size() == p.size());
  CHECK(plan.classes == 12);
  CHECK(plan.classes_needed <= 5);  // the conflict graph is the king's graph of the grid: 4
  for (int c : plan.class_of) CHECK((c >= 0 && c < 12));
  CHECK(plan.min_reuse_distance_m >= conflict);
  // 12 classes on a 2.5 m grid: a perfect lattice would reach s sqrt(12 / 0.87) = 9.3 m.
  CHECK(plan.min_reuse_distance_m >= 6.5);
  CHECK(plan.alias_fraction <= 0.3);
  INFO("reuse " << plan.min_reuse_distance_m << " m, alias " << plan.alias_fraction);
  CHECK(views_with_two_of_a_class(p, plan.class_of, cam, 3.0, 1.0, max_tilt, 20000, 7) == 0);
  // Deterministic for a seed.
  CHECK(plan_frequency_classes(p, conflict, o).class_of == plan.class_of);
}

TEST_CASE("Frequency plan: the checks can fail (a periodic tile aliases, a too-small set conflicts)", "[vlc][plan]") {
  const CameraModel cam = sim::default_sim_camera();
  const auto p = grid(24, 12, 2.5);
  std::vector<int> tile(p.size());
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 24; ++x) tile[static_cast<std::size_t>(y * 24 + x)] = (x % 4) + 4 * (y % 3);
  const AliasReport a = translational_alias(p, tile, 15.0);
  CHECK(a.fraction == Approx(1.0));
  CHECK((std::abs(a.shift.x()) == Approx(10.0) || std::abs(a.shift.y()) == Approx(7.5)));
  // Two alternating classes: neighbours two apart share a class and are seen together.
  std::vector<int> two(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) two[i] = static_cast<int>(i % 2);
  CHECK(views_with_two_of_a_class(p, two, cam, 3.0, 1.0, 15.0 * kPi / 180.0, 2000, 7) > 100);
  // Asking for fewer classes than the layout needs is refused.
  FrequencyPlanOptions o;
  o.classes = 2;
  CHECK_THROWS_AS(plan_frequency_classes(p, 4.45, o), std::invalid_argument);
}
