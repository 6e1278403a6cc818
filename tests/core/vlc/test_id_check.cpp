// Decoder id accuracy (issue 3): the matcher itself, a simulated walk with 1-4 LEDs in view
// (the dense scenario) against the renderer's truth, and dark frames.
#include <catch2/catch.hpp>
#include <algorithm>
#include <opencv2/core.hpp>

#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"
#include "core/vlc/id_check.hpp"
#include "core/vlc/stripe_decoder.hpp"

using namespace luxloc;

namespace {

LedObservation decode_at(double u, double v, int id, const std::string& reason = {}) {
  LedObservation o;
  o.uv = {u, v};
  o.led_id = id;
  o.led_index = reason.empty() ? id - 1 : -1;
  o.freq_class = o.led_index;  // a map without reuse: one class per LED
  o.reject_reason = reason;
  return o;
}

// A decode of a reused frequency: the class, no LED named.
LedObservation class_at(double u, double v, int klass) {
  LedObservation o;
  o.uv = {u, v};
  o.freq_class = klass;
  return o;
}

std::vector<TrueLedBlob> truth_of(const sim::RenderedFrame& f) {
  std::vector<TrueLedBlob> t;
  for (const sim::RenderedLed& l : f.leds) t.push_back({l.id, l.uv, l.radius_px, l.row_max - l.row_min, l.fully_inside});
  return t;
}

}  // namespace

TEST_CASE("id check: right, wrong, missed by reason, small and cut blobs not counted", "[vlc]") {
  const std::vector<TrueLedBlob> truth = {
      {1, {100, 100}, 25, 50, true},  // qualifies
      {2, {300, 100}, 25, 50, true},  // qualifies
      {3, {500, 100}, 25, 50, true},  // qualifies
      {4, {100, 400}, 8, 16, true},   // too few rows
      {5, {630, 400}, 25, 50, false}, // cut by the border
  };
  IdCheckCounts c;
  tally_ids({decode_at(101, 99, 1), decode_at(302, 101, 7), decode_at(500, 100, -1, "no stripes"),
             decode_at(100, 400, 4), decode_at(400, 300, 9)},
            truth, c);
  CHECK(c.frames == 1);
  CHECK(c.qualifying == 3);
  CHECK(c.right == 1);
  CHECK(c.missed == 2);
  CHECK(c.missed_by["wrong id"] == 1);
  CHECK(c.missed_by["no stripes"] == 1);
  CHECK(c.missed_by_id == std::map<int, long>{{2, 1}, {3, 1}});
  CHECK(c.decodes == 4);
  CHECK(c.wrong == 2);  // id 7 on LED 2, and id 9 where no LED is
  CHECK(c.rejected == 1);
  CHECK(c.dark_frames == 0);

  IdCheckCounts dark;
  tally_ids({decode_at(10, 10, 3)}, {}, dark);
  CHECK(dark.dark_frames == 1);
  CHECK(dark.dark_frame_decodes == 1);
  CHECK(dark.wrong_fraction() == 1.0);
  c.add(dark);
  CHECK(c.frames == 2);
  CHECK(c.wrong == 3);
}

TEST_CASE("id check in a map that reuses frequencies: a decode is right by class", "[vlc][reuse]") {
  // LEDs 11 and 12 share class 3; LED 13 has class 4 of its own.
  const std::vector<TrueLedBlob> truth = {{11, {100, 100}, 25, 50, true, 3},
                                          {12, {300, 100}, 25, 50, true, 3},
                                          {13, {500, 100}, 25, 50, true, 4}};
  IdCheckCounts c;
  tally_ids({class_at(101, 99, 3), class_at(300, 101, 4), decode_at(500, 100, 13)}, truth, c);
  CHECK(c.qualifying == 3);
  CHECK(c.right == 2);  // the class on LED 11, the id on LED 13
  CHECK(c.wrong == 1);  // class 4 on LED 12 (class 3)
  CHECK(c.missed_by["wrong id"] == 1);
  CHECK(c.missed_by_id == std::map<int, long>{{12, 1}});
}

TEST_CASE("simulated dense walk (1-4 whole LEDs in view): >= 99.5 % of full blobs right, <= 0.1 % wrong", "[vlc][sim]") {
  sim::SimOptions o;
  o.seed = 7;
  o.duration_s = 20.0;  // 600 frames, the start, a corner, the first straight
  const sim::Simulator s(sim::make_scenario("dense"), o);
  const StripeDecoder decoder(s.scenario().camera, s.scenario().map);
  IdCheckCounts c;
  std::vector<int> frames_with(8, 0);  // frames by number of whole LEDs (fully inside the image)
  for (std::size_t k = 0; k < s.frame_count(); ++k) {
    const sim::RenderedFrame f = s.render(k);
    const auto whole = std::count_if(f.leds.begin(), f.leds.end(), [](const sim::RenderedLed& l) { return l.fully_inside; });
    frames_with[std::min<std::size_t>(static_cast<std::size_t>(whole), 7)]++;
    tally_ids(decoder.decode(f.gray), truth_of(f), c);
  }
  INFO("frames with 0..7 whole LEDs: " << frames_with[0] << " " << frames_with[1] << " " << frames_with[2] << " "
                                       << frames_with[3] << " " << frames_with[4] << " " << frames_with[5] << " "
                                       << frames_with[6] << " " << frames_with[7]);
  INFO(c.qualifying << " qualifying, " << c.right << " right, " << c.decodes << " decodes, " << c.wrong << " wrong, "
                    << c.rejected << " rejected");
  for (const auto& [why, n] : c.missed_by) INFO("missed " << why << ": " << n);
  const int one_to_four = frames_with[1] + frames_with[2] + frames_with[3] + frames_with[4];
  CHECK(one_to_four >= 0.85 * static_cast<double>(s.frame_count()));
  CHECK(frames_with[2] + frames_with[3] + frames_with[4] >= 200);  // several LEDs at once, often
  CHECK(c.qualifying > 800);
  CHECK(c.right_fraction() >= 0.995);
  CHECK(c.wrong_fraction() <= 0.001);
}

TEST_CASE("simulated plain walk (LEDs 2 m up, 33-row stripes on 46-row discs): >= 99.5 % of full blobs right", "[vlc][sim]") {
  // The default walk: one or two LEDs in view, the 1000 Hz LED's disc shows 1.4 periods
  // and often a single bright stripe (seconds 19-21 are such a pass under LEDs 1 and 2).
  sim::SimOptions o;
  o.seed = 11;
  o.duration_s = 22.0;
  const sim::Simulator s(sim::make_scenario("walk"), o);
  const StripeDecoder decoder(s.scenario().camera, s.scenario().map);
  IdCheckCounts c;
  for (std::size_t k = 0; k < s.frame_count(); ++k) {
    const sim::RenderedFrame f = s.render(k);
    tally_ids(decoder.decode(f.gray), truth_of(f), c);
  }
  INFO(c.qualifying << " qualifying, " << c.right << " right, " << c.decodes << " decodes, " << c.wrong << " wrong");
  for (const auto& [why, n] : c.missed_by) INFO("missed " << why << ": " << n);
  for (const auto& [id, n] : c.missed_by_id) INFO("missed LED " << id << ": " << n);
  CHECK(c.qualifying > 500);
  CHECK(c.right_fraction() >= 0.995);
  CHECK(c.wrong_fraction() <= 0.001);
}

TEST_CASE("a dark frame yields no LED: blackout frames and an all-black image", "[vlc][sim]") {
  sim::SimOptions o;
  o.seed = 3;
  o.duration_s = 2.0;
  o.blackouts = {{0.0, 10.0}};
  const sim::Simulator s(sim::make_scenario("dense"), o);
  const StripeDecoder decoder(s.scenario().camera, s.scenario().map);
  IdCheckCounts c;
  for (std::size_t k = 0; k < s.frame_count(); ++k) {
    const sim::RenderedFrame f = s.render(k);
    REQUIRE(f.leds.empty());
    const auto obs = decoder.decode(f.gray);
    CHECK(obs.empty());  // not even a rejected blob: noise is not reported
    tally_ids(obs, {}, c);
  }
  CHECK(c.dark_frames == static_cast<long>(s.frame_count()));
  CHECK(c.decodes == 0);
  CHECK(decoder.decode(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0))).empty());
}
