// Trajectory metrics on hand-made trajectories with known errors.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/eval/trajectory_metrics.hpp"

using namespace luxloc;

namespace {

// Straight line along x at 1 m/s, 10 Hz truth, t in [0, duration].
std::vector<TruthRow> line_truth(double duration_s, double yaw = 0.0) {
  std::vector<TruthRow> t;
  for (int i = 0; i <= static_cast<int>(std::lround(duration_s * 10)); ++i) {
    const double s = 0.1 * i;
    t.push_back({seconds_to_ns(s), {s, 2.0, 1.0}, yaw});
  }
  return t;
}

PoseRow pose(double t, double x, double y, double yaw = std::nan("")) { return {seconds_to_ns(t), {x, y, 0.0}, yaw}; }

}  // namespace

TEST_CASE("eval: a constant 0.1 m offset gives 0.1 m everywhere", "[io]") {
  const auto truth = line_truth(10.0);
  std::vector<PoseRow> poses;
  for (int i = 0; i < 100; ++i) {
    const double t = 0.05 + 0.1 * i;            // between truth rows: interpolation needed
    poses.push_back(pose(t, t + 0.06, 2.08));  // offset (0.06, 0.08): 0.1 m
  }
  const EvalResult r = evaluate(truth, poses);
  CHECK(r.n == 100);
  CHECK(r.n_outside == 0);
  CHECK(r.rmse_m == Approx(0.1));
  CHECK(r.mean_m == Approx(0.1));
  CHECK(r.median_m == Approx(0.1));
  CHECK(r.p95_m == Approx(0.1));
  CHECK(r.max_m == Approx(0.1));
  CHECK(r.coverage == Approx(1.0));
  CHECK(r.n_yaw == 0);
  CHECK(std::isnan(r.yaw_rmse_rad));
  CHECK(format_eval_summary(r) == "ATE RMSE 0.100 m | median 0.100 | p95 0.100 | max 0.100 | n 100 | coverage 100.0 %");
}

TEST_CASE("eval: known error distribution -> RMSE, median, p95, max", "[io]") {
  const auto truth = line_truth(10.0);
  // Errors 0.01, 0.02, ..., 1.00 m (y offset), shuffled in time order.
  std::vector<PoseRow> poses;
  for (int k = 1; k <= 100; ++k) {
    const int slot = (k * 37) % 100;  // a permutation of 0..99
    const double t = 0.1 * slot;
    poses.push_back(pose(t, t, 2.0 + 0.01 * k));
  }
  const EvalResult r = evaluate(truth, poses);
  REQUIRE(r.n == 100);
  double sq = 0;
  for (int k = 1; k <= 100; ++k) sq += 0.0001 * k * k;
  CHECK(r.rmse_m == Approx(std::sqrt(sq / 100)));
  CHECK(r.median_m == Approx(0.505));          // between the 50th and 51st
  CHECK(r.p95_m == Approx(0.9505));            // numpy: 0.01 + 0.95 * 99 * 0.01
  CHECK(r.max_m == Approx(1.0));
  CHECK(r.t_max == seconds_to_ns(0.1 * ((100 * 37) % 100)));
  // errors come out in time order
  for (std::size_t i = 1; i < r.errors.size(); ++i) CHECK(r.errors[i].t > r.errors[i - 1].t);
}

TEST_CASE("eval: truth interpolation is linear, yaw along the shorter arc", "[io]") {
  std::vector<TruthRow> truth = {{0, {0, 0, 0}, 3.0}, {seconds_to_ns(2.0), {2, 4, 1}, -3.0}};
  TruthRow g;
  REQUIRE(interpolate_truth(truth, seconds_to_ns(0.5), g));
  CHECK(g.p_inW.x() == Approx(0.5));
  CHECK(g.p_inW.y() == Approx(1.0));
  CHECK(g.p_inW.z() == Approx(0.25));
  // 3.0 -> -3.0 crosses pi: the midpoint is pi, not 0.
  REQUIRE(interpolate_truth(truth, seconds_to_ns(1.0), g));
  CHECK(std::abs(wrap_angle(g.yaw - std::numbers::pi)) < 1e-9);
  CHECK_FALSE(interpolate_truth(truth, seconds_to_ns(-0.1), g));
  CHECK_FALSE(interpolate_truth(truth, seconds_to_ns(2.1), g));
  REQUIRE(interpolate_truth(truth, seconds_to_ns(2.0), g));
  CHECK(g.p_inW.y() == Approx(4.0));
}

TEST_CASE("eval: poses outside the truth span are ignored and counted", "[io]") {
  const auto truth = line_truth(5.0);
  std::vector<PoseRow> poses = {pose(-1.0, 0, 0), pose(1.0, 1.0, 2.3), pose(6.0, 0, 0), pose(5.0, 5.0, 2.0)};
  const EvalResult r = evaluate(truth, poses);
  CHECK(r.n == 2);
  CHECK(r.n_outside == 2);
  CHECK(r.max_m == Approx(0.3));
}

TEST_CASE("eval: coverage counts the 1-s bins of the truth span holding a pose", "[io]") {
  const auto truth = line_truth(10.0);
  std::vector<PoseRow> poses;
  // Poses every 0.1 s except a gap over [3, 7): bins 3, 4, 5, 6 empty -> 6 of 10 s.
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.1 * i;
    if (t >= 2.95 && t < 6.95) continue;
    poses.push_back(pose(t, t, 2.0));
  }
  EvalResult r = evaluate(truth, poses);
  CHECK(r.coverage == Approx(0.6));
  // A final partial bin counts by its length: span 10.5 s, only the last 0.5-s bin covered.
  auto truth2 = line_truth(10.5);
  r = evaluate(truth2, {pose(10.4, 10.4, 2.0)});
  CHECK(r.coverage == Approx(0.5 / 10.5));
  // Wider bins on request.
  EvalOptions o;
  o.coverage_bin_s = 5.0;
  r = evaluate(truth, poses, o);
  CHECK(r.coverage == Approx(1.0));
  CHECK(evaluate(truth, {}).coverage == 0.0);
}

TEST_CASE("eval: yaw RMSE wraps angles", "[io]") {
  const auto truth = line_truth(2.0, 3.1);
  // Estimate yaw -3.1: the true difference is 2*pi - 6.2 = 0.0832 rad, not 6.2.
  const EvalResult r = evaluate(truth, {pose(0.5, 0.5, 2.0, -3.1), pose(1.0, 1.0, 2.0, 3.0), pose(1.5, 1.5, 2.0)});
  CHECK(r.n == 3);
  CHECK(r.n_yaw == 2);
  const double d1 = 2 * std::numbers::pi - 6.2, d2 = 0.1;
  CHECK(r.yaw_rmse_rad == Approx(std::sqrt((d1 * d1 + d2 * d2) / 2)));
  CHECK_THAT(format_eval_summary(r), Catch::Contains("yaw RMSE"));
  CHECK(wrap_angle(std::numbers::pi) == Approx(std::numbers::pi));
  CHECK(wrap_angle(-std::numbers::pi) == Approx(std::numbers::pi));
  CHECK(wrap_angle(7.0) == Approx(7.0 - 2 * std::numbers::pi));
}

TEST_CASE("eval: JSON has no NaN, bad truth order is refused", "[io]") {
  const auto truth = line_truth(2.0);
  const std::string j = format_eval_json(evaluate(truth, {pose(0.5, 0.5, 2.1)}));
  CHECK_THAT(j, Catch::Contains("\"ate_rmse_m\":0.100000"));
  CHECK(j.find("nan") == std::string::npos);
  CHECK(j.find("yaw_rmse_rad") == std::string::npos);
  auto bad = truth;
  std::swap(bad[3], bad[4]);
  CHECK_THROWS_AS(evaluate(bad, {}), std::invalid_argument);
  CHECK(percentile({}, 0.5) != percentile({}, 0.5));  // NaN for no data
  CHECK(percentile({3.0}, 0.95) == 3.0);
}

TEST_CASE("eval: sigma consistency counts the poses inside their own 95 % region, yaw percentiles", "[io]") {
  const auto truth = line_truth(10.0);
  std::vector<PoseRow> poses;
  for (int i = 0; i < 100; ++i) {
    const double t = 0.05 + 0.1 * i;
    // 0.1 m off along y; the first 60 claim sigma 0.05 (2 sigma: inside the 2.45-sigma
    // circle), the rest 0.02 (5 sigma: outside). Yaw 1 deg off, sigma_yaw 1 deg (inside
    // 1.96 sigma) for the first half, 0.25 deg (outside) for the rest.
    PoseRow p = pose(t, t, 2.1, std::numbers::pi / 180.0);
    p.sigma_x = p.sigma_y = i < 60 ? 0.05 : 0.02;
    p.sigma_yaw = (i < 50 ? 1.0 : 0.25) * std::numbers::pi / 180.0;
    poses.push_back(p);
  }
  const EvalResult r = evaluate(truth, poses);
  CHECK(r.n_sigma == 100);
  CHECK(r.consistency == Approx(0.60));
  CHECK(r.mean_sigma_m == Approx(0.6 * 0.05 + 0.4 * 0.02));
  CHECK(r.n_sigma_yaw == 100);
  CHECK(r.yaw_consistency == Approx(0.50));
  CHECK(r.yaw_p95_rad == Approx(std::numbers::pi / 180.0));
  CHECK(r.yaw_max_rad == Approx(std::numbers::pi / 180.0));
  CHECK(format_eval_summary(r).find("within 95 % 60.0 %") != std::string::npos);
  CHECK(format_eval_json(r).find("\"consistency\":0.600000") != std::string::npos);
  // Without sigma columns: no consistency, and the JSON leaves it out.
  const EvalResult plain = evaluate(truth, {pose(1.0, 1.0, 2.0)});
  CHECK(plain.n_sigma == 0);
  CHECK(std::isnan(plain.consistency));
  CHECK(format_eval_json(plain).find("consistency") == std::string::npos);
}
