// Issue 16 parts 1 and 6: `--motion auto` tells a gait from rotor vibration (the drone is
// never walked with the pedestrian model, a walker is), and the UWB summary counts add up.
#include <catch2/catch.hpp>
#include <algorithm>
#include <map>

#include "core/fusion/fusion_engine.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;

namespace {

struct Run {
  std::uint64_t steps = 0, steps_used = 0, uwb_samples = 0;
  std::array<double, 4> regime_s{};
  std::map<std::string, std::size_t> pose_motion;  // poses per `motion` column value
  std::size_t poses = 0;
  UwbStats uwb;
  double motion_share(const std::string& name) const {
    const auto it = pose_motion.find(name);
    return it == pose_motion.end() ? 0.0 : static_cast<double>(it->second) / static_cast<double>(poses);
  }
};

Run run_auto(const std::string& scenario, std::uint64_t seed, double duration_s, bool ekf = false) {
  sim::SimOptions o;
  o.seed = seed;
  o.duration_s = duration_s;
  const sim::Simulator simulator(sim::make_scenario(scenario), o);
  std::vector<Sample> samples;
  for (const ImuSample& m : simulator.imu_samples()) {
    Sample x;
    x.t = m.t;
    x.data.emplace<ImuSample>(m);
    samples.push_back(x);
  }
  Run r;
  for (const sim::SimUwbMeasurement& m : simulator.uwb_measurements()) {
    Sample x;
    x.t = m.sample.t;
    x.source = 1;
    x.data.emplace<UwbSample>(m.sample);
    samples.push_back(x);
    ++r.uwb_samples;
  }
  std::stable_sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.t < b.t; });
  SessionConfig config;
  config.device_height_m = simulator.scenario().device_height_m;
  config.anchors = simulator.scenario().anchors;
  FusionOptions f;
  f.motion.model = MotionModel::pdr;
  f.motion.gait_gate = true;  // what run_session sets for --motion auto
  if (ekf) f.filter = "ekf";
  FusionEngine engine(f, std::nullopt, std::nullopt, config, UwbOptions{});
  std::vector<PoseEstimate> out;
  for (const Sample& x : samples) engine.process(x, out);
  engine.finish(out);
  for (const PoseEstimate& p : out) ++r.pose_motion[p.motion];
  r.poses = out.size();
  r.steps = engine.motion().steps();
  r.steps_used = engine.motion().steps_used();
  r.regime_s = engine.motion().regime_seconds();
  r.uwb = engine.uwb_stats();
  return r;
}

constexpr std::size_t kGait = static_cast<std::size_t>(MotionRegime::gait);

}  // namespace

TEST_CASE("motion auto never walks the drone with the pedestrian model", "[motion][platform]") {
  const Run r = run_auto("drone", 101, 30.0);
  CHECK(r.steps > 20);  // the vibration does fire the step detector...
  CHECK(r.steps_used == 0);  // ...but no step reaches the gait speed
  CHECK(r.regime_s[kGait] == 0.0);
  CHECK(r.regime_s[static_cast<std::size_t>(MotionRegime::strapdown)] > 25.0);
  // The pose output says so, pose by pose (the `motion` column).
  REQUIRE(r.poses > 1000);
  CHECK(r.pose_motion.count("walking") == 0);
  CHECK(r.motion_share("moving") > 0.8);
}

TEST_CASE("motion auto walks a walker with the pedestrian model", "[motion][platform]") {
  const Run r = run_auto("uwb", 102, 40.0);
  CHECK(r.steps > 40);
  CHECK(r.steps_used == r.steps);  // the run of steps that proved the gait is replayed
  CHECK(r.regime_s[kGait] > 25.0);
  REQUIRE(r.poses > 1000);
  CHECK(r.motion_share("walking") > 0.6);
  CHECK(r.pose_motion.count("constant-velocity") == 0);
  for (const auto& [name, n] : r.pose_motion)
    CHECK((name == "walking" || name == "moving" || name == "still"));
}

TEST_CASE("UWB summary counts add up to the measurements", "[uwb][platform]") {
  for (const bool ekf : {false, true}) {
    const Run r = run_auto("drone", 103, 20.0, ekf);
    INFO("ekf " << ekf);
    CHECK(r.uwb.samples == r.uwb_samples);
    CHECK(r.uwb.accounted() == r.uwb.samples);
    if (ekf)  // the EKF takes position fixes only (one per epoch of 8 ranges): the rest wait for one
      CHECK(r.uwb.fixes_used + r.uwb.fixes_gated + r.uwb.no_fix > r.uwb.samples * 9 / 10);
    else
      CHECK(r.uwb.weighed > r.uwb.samples / 2);
  }
}
