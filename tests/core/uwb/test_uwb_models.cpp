// UWB measurement models: robust NLOS likelihood, seed B.3 fix, multilateration, frontend.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "core/uwb/multilateration.hpp"
#include "core/uwb/tof_aoa_fix.hpp"
#include "core/uwb/uwb_frontend.hpp"
#include "core/uwb/uwb_noise_model.hpp"
#include "core/uwb/uwb_range_likelihood.hpp"

using namespace luxloc;

TEST_CASE("UWB noise model: the robust tail is one-sided, the Gaussian is not robust", "[uwb]") {
  UwbNoiseModel robust;
  UwbNoiseModel gauss;
  gauss.likelihood = UwbLikelihood::gaussian;
  // Near zero both agree closely (the core dominates).
  CHECK(robust.range_log_likelihood(0.0) == Approx(gauss.range_log_likelihood(0.0)).margin(0.1));
  // A 1 m positive residual (NLOS) stays plausible under the robust model...
  CHECK(robust.range_log_likelihood(1.0) - robust.range_log_likelihood(0.0) > -6.0);
  CHECK(gauss.range_log_likelihood(1.0) - gauss.range_log_likelihood(0.0) < -49.0);
  // ...a 1 m negative one (shorter than the direct path) does not: far less likely than +1 m.
  CHECK(robust.range_log_likelihood(-1.0) < robust.range_log_likelihood(1.0) - 2.0);
  // The floor keeps any residual finite.
  CHECK(std::isfinite(robust.range_log_likelihood(-50.0)));
  CHECK(std::isfinite(robust.range_aoa_log_likelihood(40.0, 3.0)));
  // The ex-Gaussian is a density: integrates to ~1 (both branches of its evaluation).
  double s = 0.0;
  for (double e = -2.0; e < 30.0; e += 0.001) s += std::exp(robust.log_exgauss(e)) * 0.001;
  CHECK(s == Approx(1.0).margin(0.01));
  // Bearing errors wrap: +pi - eps and -pi + eps are neighbours.
  CHECK(robust.range_aoa_log_likelihood(0.0, std::numbers::pi - 0.01) ==
        Approx(robust.range_aoa_log_likelihood(0.0, -std::numbers::pi + 0.01)));
}

TEST_CASE("Seed B.3 TOF+AOA fix: exact without noise, horizontal range from the 3-D one", "[uwb]") {
  const Eigen::Vector3d anchor(4.0, 3.0, 2.8);
  const Eigen::Vector3d device(6.5, 1.0, 1.0);
  UwbSample s;
  s.anchor = 1;
  s.range_m = (device - anchor).norm();
  s.aoa_rad = std::atan2(device.y() - anchor.y(), device.x() - anchor.x());
  const auto m = tof_aoa_fix(s, anchor, device.z(), UwbNoiseModel{});
  REQUIRE(m);
  CHECK(m->z.x() == Approx(6.5).margin(1e-9));
  CHECK(m->z.y() == Approx(1.0).margin(1e-9));
  // Covariance: along the bearing ~ (d / r) * range sigma, across it ~ r * aoa sigma.
  const Eigen::Vector2d u = (device - anchor).head<2>().normalized();
  const double r = (device - anchor).head<2>().norm();
  CHECK(std::sqrt(u.dot(m->R * u)) == Approx(s.range_m / r * 0.10).epsilon(1e-6));
  const Eigen::Vector2d n(-u.y(), u.x());
  CHECK(std::sqrt(n.dot(m->R * n)) == Approx(r * 0.05).epsilon(1e-6));
  s.aoa_rad = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(tof_aoa_fix(s, anchor, device.z(), UwbNoiseModel{}));
  // Range shorter than the height difference: under the anchor, not NaN.
  s.aoa_rad = 0.3;
  s.range_m = 1.5;
  const auto under = tof_aoa_fix(s, anchor, device.z(), UwbNoiseModel{});
  REQUIRE(under);
  CHECK(under->z.isApprox(anchor.head<2>()));
}

TEST_CASE("Multilateration: Gauss-Newton from 4 anchors, robust to one NLOS range", "[uwb]") {
  const std::vector<Eigen::Vector3d> anchors = {{0, 0, 2.5}, {8, 0, 2.4}, {8, 6, 2.6}, {0, 6, 2.5}, {4, 3, 2.9}};
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 0.05);
  double worst = 0.0, worst_nlos = 0.0, worst_ls = 0.0;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d p(0.5 + 0.14 * k, 0.4 + 0.1 * k, 1.0);
    std::vector<RangeToAnchor> r;
    for (const auto& a : anchors) r.push_back({a, (p - a).norm() + n(rng)});
    const auto m = multilaterate(r, 1.0);
    REQUIRE(m);
    worst = std::max(worst, (m->fix.z - p.head<2>()).norm());
    r[k % 5].range_m += 1.5;  // one NLOS range
    MultilaterationOptions plain;
    plain.huber_k = 0.0;
    plain.max_rms_m = 10.0;
    const auto robust = multilaterate(r, 1.0);
    const auto ls = multilaterate(r, 1.0, plain);
    REQUIRE(robust);
    REQUIRE(ls);
    worst_nlos = std::max(worst_nlos, (robust->fix.z - p.head<2>()).norm());
    worst_ls = std::max(worst_ls, (ls->fix.z - p.head<2>()).norm());
  }
  CHECK(worst < 0.15);
  CHECK(worst_nlos < 0.5);
  CHECK(worst_nlos < 0.6 * worst_ls);  // Huber weighting beats plain least squares
  // Too few or collinear anchors: no fix.
  CHECK_FALSE(multilaterate({{anchors[0], 3.0}, {anchors[1], 4.0}}, 1.0));
  CHECK_FALSE(multilaterate({{{0, 0, 2}, 3.0}, {{2, 0, 2}, 2.0}, {{4, 0, 2}, 2.5}}, 1.0));
}

TEST_CASE("UWB particle likelihood peaks at the device, the frontend groups ranges and learns anchors", "[uwb]") {
  const Eigen::Vector3d anchor(4.0, 3.0, 2.8);
  const Eigen::Vector3d device(2.0, 1.5, 1.0);
  const double d = (device - anchor).norm();
  const double th = std::atan2(device.y() - anchor.y(), device.x() - anchor.x());
  const UwbRangeLikelihood lik(anchor, 1.0, d, th, UwbNoiseModel{});
  const double at = lik(device.x(), device.y());
  for (double dx : {-0.3, 0.3})
    for (double dy : {-0.3, 0.3}) CHECK(lik(device.x() + dx, device.y() + dy) < at - 1.0);
  // The mirror point (same range, opposite bearing) is ruled out by the AOA only.
  const Eigen::Vector2d mirror = 2.0 * anchor.head<2>() - device.head<2>();
  CHECK(lik(mirror.x(), mirror.y()) < at - 15.0);
  const UwbRangeLikelihood ring(anchor, 1.0, d, std::numeric_limits<double>::quiet_NaN(), UwbNoiseModel{});
  CHECK(ring(mirror.x(), mirror.y()) == Approx(ring(device.x(), device.y())).margin(1e-9));

  // Frontend: 3 anchors without AOA; the third range of a group yields a fix.
  UwbFrontend fe(UwbOptions{}, UwbAnchorTable({{1, {0, 0, 2.5}}, {2, {8, 0, 2.5}}}), 1.0);
  std::vector<UwbSample> line;
  const Eigen::Vector3d third(4, 6, 2.5);
  for (auto [id, a] : {std::pair{1, Eigen::Vector3d(0, 0, 2.5)}, {2, Eigen::Vector3d(8, 0, 2.5)}, {3, third}}) {
    UwbSample s;
    s.t = 1'000'000'000;
    s.anchor = id;
    s.range_m = (device - a).norm();
    if (id == 3) s.p_AinW = third;  // reported by the device (DWM1001), not configured
    line.push_back(s);
  }
  int fixes = 0;
  for (const UwbSample& s : line) {
    REQUIRE(fe.likelihood(s));
    if (const auto m = fe.fix(s)) {
      ++fixes;
      CHECK((m->z - device.head<2>()).norm() < 1e-6);
    }
  }
  CHECK(fixes == 1);
  CHECK(fe.stats().learnt_anchors == 1);
  UwbSample unknown = line[0];
  unknown.anchor = 99;
  CHECK_FALSE(fe.likelihood(unknown));
  CHECK(fe.stats().unknown_anchor == 1);
}

TEST_CASE("Multilateration: a fix outside the anchors' hull is flagged, one inside is not", "[uwb]") {
  // Issue 16 part 4: anchors along one wall see a point and its mirror through the wall alike;
  // the fix may be either, so it must say it lies outside the anchors.
  const std::vector<Eigen::Vector3d> wall = {{0, 0, 2.5}, {3, 0.3, 2.5}, {6, 0, 2.5}, {9, 0.3, 2.5}};
  const std::vector<Eigen::Vector3d> room = {{0, 0, 2.5}, {8, 0, 0.3}, {8, 6, 2.5}, {0, 6, 0.3}};
  const auto ranges = [](const std::vector<Eigen::Vector3d>& anchors, const Eigen::Vector3d& p) {
    std::vector<RangeToAnchor> r;
    for (const auto& a : anchors) r.push_back({a, (p - a).norm()});
    return r;
  };
  const auto out = multilaterate(ranges(wall, {4.5, 4.0, 1.0}), 1.0);
  REQUIRE(out);
  CHECK(out->outside_hull);
  CHECK(std::abs(std::abs(out->fix.z.y()) - 4.0) < 0.3);  // the point or its mirror, flagged either way
  const auto in = multilaterate(ranges(room, {2.0, 1.5, 1.0}), 1.0);
  REQUIRE(in);
  CHECK_FALSE(in->outside_hull);
  CHECK((in->fix.z - Eigen::Vector2d(2.0, 1.5)).norm() < 0.01);
}
