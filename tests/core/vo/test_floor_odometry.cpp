// Downward-camera visual odometry (SEEDS.md C.5) on rendered floor frames, and seed C's
// VO + IMU fusion on the `floor` scenario (issue 6 done-when: final drift <= 2 %).
#include <catch2/catch.hpp>
#include <cmath>

#include "core/fusion/fusion_engine.hpp"
#include "core/sim/floor_renderer.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"
#include "core/vo/floor_odometry.hpp"

using namespace luxloc;

namespace {

Eigen::Isometry3d pose(double x, double y, double yaw, double z = 1.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace

TEST_CASE("Floor VO: frame-to-frame motion of a downward camera, in body axes, to the millimetre", "[vo]") {
  const CameraModel cam = sim::floor_sim_camera();
  const sim::FloorRenderer floor(cam, -1.0, -1.0, 4.0, 4.0, 0.003, 4);
  std::mt19937_64 rng(1);
  FloorOdometry vo(cam, 1.0);
  double x = 1.0, y = 1.0, yaw = 0.3;
  REQUIRE_FALSE(vo.process(floor.render(pose(x, y, yaw), rng), 0));
  const double step_fwd = 0.03, step_left = -0.01, dyaw = 0.02;
  for (int k = 1; k <= 20; ++k) {
    // Move 3 cm forward and 1 cm right in the body frame, turn 0.02 rad left.
    x += std::cos(yaw) * step_fwd - std::sin(yaw) * step_left;
    y += std::sin(yaw) * step_fwd + std::cos(yaw) * step_left;
    yaw += dyaw;
    const auto m = vo.process(floor.render(pose(x, y, yaw), rng), k * 33'333'333LL);
    REQUIRE(m);
    // Displacement in the previous body frame: (3 cm, -1 cm) rotated by nothing (the turn
    // happens at the end point); compare within 2 mm and 0.1 deg.
    CHECK(m->d_inB.x() == Approx(step_fwd).margin(0.002));
    CHECK(m->d_inB.y() == Approx(step_left).margin(0.002));
    CHECK(m->dyaw_rad == Approx(dyaw).margin(0.0017));
    CHECK(m->scale == Approx(1.0).margin(0.01));
    CHECK(m->inliers > 50);
    CHECK(m->dt_s == Approx(1.0 / 30).margin(1e-6));
  }
  // A blank frame: no motion, then it restarts.
  CHECK_FALSE(vo.process(cv::Mat(240, 320, CV_8UC1, cv::Scalar(128)), 700'000'000));
}

TEST_CASE("Seed C on the floor scenario: IMU + VO through the PF, final drift <= 2 % of the distance", "[vo][fusion]") {
  sim::SimOptions o;
  o.seed = 2;
  o.duration_s = 25.0;
  const sim::Simulator simulator(sim::make_scenario("floor"), o);
  const sim::Scenario& sc = simulator.scenario();
  std::vector<Sample> samples;
  for (const ImuSample& m : simulator.imu_samples()) {
    Sample x;
    x.t = m.t;
    x.data.emplace<ImuSample>(m);
    samples.push_back(std::move(x));
  }
  const std::size_t n_imu = samples.size();
  for (std::size_t k = 0; k < simulator.frame_count(); ++k) {
    Sample x;
    x.t = seconds_to_ns(simulator.frame_time_s(k));
    x.source = 1;
    FrameSample f;
    f.t = x.t;
    f.gray = simulator.render(k).gray;
    x.data = std::move(f);
    samples.push_back(std::move(x));
  }
  {
    Sample x;
    x.source = 2;
    FixSample f;
    f.p_inW = simulator.truth(0.0).p_BinW.head<2>();
    f.sigma_m = 0.02;
    x.data = f;
    samples.push_back(std::move(x));
  }
  std::stable_sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.t < b.t; });
  REQUIRE(samples.size() == n_imu + 750 + 1);
  SessionConfig cfg;
  cfg.device_height_m = sc.device_height_m;

  const auto run = [&](const std::string& filter, bool vo_on) {
    FusionOptions f;
    f.filter = filter;
    f.motion.model = MotionModel::strapdown;  // seed C: strapdown + VO (a ride, no steps)
    VoOptions vo;
    vo.enabled = vo_on;
    FusionEngine engine(f, std::nullopt, sc.camera, cfg, UwbOptions{}, vo);
    std::vector<PoseEstimate> out;
    for (const Sample& s : samples) engine.process(s, out);
    engine.finish(out);
    REQUIRE(!out.empty());
    double dist = 0.0;
    for (double t = 0.01; t <= ns_to_seconds(out.back().t); t += 0.01)
      dist += (simulator.truth(t).p_BinW - simulator.truth(t - 0.01).p_BinW).head<2>().norm();
    const double drift = (out.back().p_BinW - simulator.truth(ns_to_seconds(out.back().t)).p_BinW).head<2>().norm();
    return std::pair{drift / dist, engine.vo_stats()};
  };
  const auto [pf, pf_stats] = run("pf", true);
  const auto [ekf, ekf_stats] = run("ekf", true);
  const auto [imu_only, imu_stats] = run("pf", false);
  WARN("floor scenario, 25 s: final drift PF + VO " << 100 * pf << " %, EKF + VO " << 100 * ekf
                                                    << " %, IMU only " << 100 * imu_only << " % of the distance");
  CHECK(pf <= 0.02);
  CHECK(ekf <= 0.02);
  CHECK(imu_only > 0.05);  // the accelerometer alone cannot carry 18 m
  CHECK(pf_stats.accepted > 700);
  CHECK(imu_stats.frames == 0);
}
