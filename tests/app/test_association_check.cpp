// run --check-associations' judge (issue 14): a reused blob given the copy the renderer
// really put there counts right, another copy wrong, and a search is not judged.
#include <catch2/catch.hpp>

#include "app/association_check.hpp"
#include "core/sim/scenario.hpp"

using namespace luxloc;

TEST_CASE("Association check: right copy, wrong copy, searching and no true LED are told apart", "[reuse]") {
  const sim::Scenario s = sim::make_scenario("floorplan");
  // Standing still and level under LED 100, for 2 s.
  const Led& led = s.map.leds()[99];
  app::SimTruth truth;
  truth.has_tilt = truth.has_z = true;
  for (double t : {0.0, 2.0}) truth.rows.push_back({t, Eigen::Vector3d(led.p_inW.x(), led.p_inW.y(), 1.0), 0.0, 0.0, 0.0});
  sim::RenderOptions render;
  std::mt19937_64 rng(1);
  const std::vector<TrueLedBlob> seen = app::true_led_blobs(truth, s.camera, s.map, 1.0, render, rng);
  const TrueLedBlob* above = nullptr;
  for (const TrueLedBlob& b : seen)
    if (b.id == led.id) above = &b;
  REQUIRE(above);
  const int k = s.map.class_of(99);
  int other = -1;  // another copy of the class
  for (int m : s.map.classes()[static_cast<std::size_t>(k)].members)
    if (m != 99) other = m;
  REQUIRE(other >= 0);
  using Record = FusionEngine::AssociationRecord;
  std::vector<Record> records(4);
  for (Record& r : records) r.t_frame = 1'000'000'000;
  records[0].blobs = {{above->uv, k, 99}};                                 // right
  records[1].blobs = {{above->uv, k, other}, {above->uv, k, -1}};          // wrong, and no copy chosen
  records[2].localising = true;
  records[2].blobs = {{above->uv, k, other}};                              // searching: not judged
  records[3].blobs = {{Eigen::Vector2d(5, 5), k, 99}};                     // nothing rendered there
  const app::AssociationCheck c = app::check_associations(records, truth, {}, s.camera, s.map);
  CHECK(c.frames == 4);
  CHECK(c.blobs == 5);
  CHECK(c.localising == 1);
  CHECK(c.judged == 4);
  CHECK(c.right == 1);
  CHECK(c.wrong == 1);
  CHECK(c.unassociated == 1);
  CHECK(c.no_truth == 1);
  CHECK(c.wrong_frames == 1);
  CHECK(c.first_wrong_s == Approx(1.0));
  CHECK_THAT(app::describe(c), Catch::Contains("wrong copy 1 in 1 frames"));
  // In a blackout nothing is seen: every judged blob has no true LED.
  const app::AssociationCheck dark = app::check_associations(records, truth, {{0.5, 1.0}}, s.camera, s.map);
  CHECK(dark.no_truth == 4);
  CHECK(dark.wrong == 0);
}
