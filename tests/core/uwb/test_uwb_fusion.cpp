// Done-when of issue 6 (UWB): on the simulated 120 s single-base-station session (TOF + AOA,
// 5 % NLOS), UWB fused with the IMU reaches ATE RMSE <= 0.15 m and beats UWB alone and
// seed A's plain particle filter on the same data.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "core/fusion/fusion_engine.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;

namespace {

struct Session {
  std::vector<Sample> samples;  // IMU and UWB merged in time order
  sim::Simulator simulator;
  SessionConfig config;
  std::size_t nlos = 0, uwb = 0;
};

Session make_session(std::uint64_t seed) {
  sim::SimOptions o;
  o.seed = seed;
  Session s{{}, sim::Simulator(sim::make_scenario("uwb"), o), {}};
  const std::vector<ImuSample> imu = s.simulator.imu_samples();
  const std::vector<sim::SimUwbMeasurement> uwb = s.simulator.uwb_measurements();
  s.samples.resize(imu.size() + uwb.size());
  for (std::size_t i = 0; i < imu.size(); ++i) {
    s.samples[i].t = imu[i].t;
    s.samples[i].data.emplace<ImuSample>(imu[i]);
  }
  for (std::size_t i = 0; i < uwb.size(); ++i) {
    const sim::SimUwbMeasurement& m = uwb[i];
    Sample& x = s.samples[imu.size() + i];
    x.t = m.sample.t;
    x.source = 1;
    x.data.emplace<UwbSample>(m.sample);
    s.nlos += m.nlos;
    ++s.uwb;
  }
  std::stable_sort(s.samples.begin(), s.samples.end(), [](const Sample& a, const Sample& b) { return a.t < b.t; });
  s.config.device_height_m = s.simulator.scenario().device_height_m;
  s.config.anchors = s.simulator.scenario().anchors;
  return s;
}

struct Result {
  double rmse = 0.0, max = 0.0;
  std::size_t poses = 0;
  UwbStats stats;
};

Result run(const Session& s, FusionOptions f, const UwbOptions& u) {
  FusionEngine engine(f, std::nullopt, std::nullopt, s.config, u);
  std::vector<PoseEstimate> out;
  for (const Sample& x : s.samples) engine.process(x, out);
  engine.finish(out);
  Result r;
  double sum = 0.0;
  for (const PoseEstimate& p : out) {
    REQUIRE(p.p_BinW.allFinite());
    const double e = (p.p_BinW.head<2>() - s.simulator.truth(ns_to_seconds(p.t)).p_BinW.head<2>()).norm();
    sum += e * e;
    r.max = std::max(r.max, e);
  }
  r.poses = out.size();
  r.rmse = out.empty() ? 1e9 : std::sqrt(sum / static_cast<double>(out.size()));
  r.stats = engine.uwb_stats();
  return r;
}

}  // namespace

TEST_CASE("UWB TOF+AOA + IMU on the 120 s uwb scenario: ATE <= 0.15 m, better than UWB alone and plain PF",
          "[uwb][fusion]") {
  const Session s = make_session(1);
  REQUIRE(s.uwb == 1200);
  // About 5 % NLOS outliers, as specified.
  CHECK(s.nlos > 40);
  CHECK(s.nlos < 80);

  FusionOptions f;
  f.pf.seed = 3;
  UwbOptions robust;  // defaults: tight coupling, robust NLOS likelihood

  UwbOptions alone;
  alone.fixes_only = true;

  FusionOptions plain_f = f;  // seed A: loose fix, Gaussian weighting, resample every fix
  plain_f.tight_coupling = false;
  plain_f.pf.resample_every_correction = true;
  UwbOptions plain;
  plain.noise.likelihood = UwbLikelihood::gaussian;

  UwbOptions gaussian_tight;
  gaussian_tight.noise.likelihood = UwbLikelihood::gaussian;

  const Result best = run(s, f, robust);
  const Result uwb_alone = run(s, f, alone);
  const Result plain_pf = run(s, plain_f, plain);
  const Result tight_gauss = run(s, f, gaussian_tight);
  WARN("ATE RMSE: fused robust " << best.rmse << " m (max " << best.max << "), UWB alone " << uwb_alone.rmse
                                 << " m, plain PF " << plain_pf.rmse << " m, tight Gaussian " << tight_gauss.rmse
                                 << " m");
  CHECK(best.poses > 5000);  // 50 Hz over ~120 s
  CHECK(uwb_alone.poses == 1200);
  CHECK(best.rmse <= 0.15);
  CHECK(best.rmse < 0.8 * uwb_alone.rmse);
  // Against the plain PF the margin on one filter seed is ~1 %, within the seed-to-seed
  // spread: compared over three filter seeds (the mean ATE), not on one draw.
  double best_sum = 0.0, plain_sum = 0.0;
  for (std::uint64_t pf_seed : {3u, 4u, 5u}) {
    FusionOptions a = f, b = plain_f;
    a.pf.seed = b.pf.seed = pf_seed;
    best_sum += run(s, a, robust).rmse;
    plain_sum += run(s, b, plain).rmse;
  }
  INFO("mean over filter seeds 3-5: robust " << best_sum / 3 << " m, plain PF " << plain_sum / 3 << " m");
  CHECK(best_sum < plain_sum);
  CHECK(best.rmse < tight_gauss.rmse);
  CHECK(best.stats.weighed > 1100);
  CHECK(best.stats.reinitializations == 0);
}
