// Per-particle association of reused frequencies in the tight-coupling likelihood (issue
// 14): each particle takes the copy its own pose points the bearing at.
#include <catch2/catch.hpp>

#include "core/fusion/reprojection_likelihood.hpp"
#include "core/sim/scenario.hpp"

using namespace luxloc;

namespace {
Led led(int id, double f, double x, double y) {
  Led l;
  l.id = id;
  l.freq_hz = f;
  l.p_inW = {x, y, 3.0};
  return l;
}
Eigen::Vector2d pixel_of(const CameraModel& cam, const Eigen::Vector3d& p_L, const Eigen::Vector3d& p_B) {
  const Eigen::Vector3d p_LinC = cam.R_CtoB.transpose() * (p_L - p_B) - cam.R_CtoB.transpose() * cam.p_CinB;
  Eigen::Vector2d uv;
  REQUIRE(cam.project(p_LinC, uv));
  return uv;
}
}  // namespace

TEST_CASE("Reprojection with reuse: each particle associates the copy under it, and resolved() fixes one", "[fusion][reuse]") {
  const CameraModel cam = sim::default_sim_camera();
  // Class 1000 Hz at x = 0 and x = 8 (8 m reuse), class 1600 Hz once, at (4, 5).
  const LedMap map({led(1, 1000, 0, 0), led(2, 1000, 8, 0), led(3, 1600, 4, 5)}, "m");
  const LedClassIndex index(map);
  const Eigen::Vector3d p_B(0.4, -0.3, 1.0);
  const Eigen::Vector2d uv = pixel_of(cam, map.leds()[0].p_inW, p_B);
  const ReprojectionTerm t{Eigen::Vector3d::Zero(), uv, 1.0 / 4.0, map.class_of(0)};
  const ReprojectionLikelihood lik(cam, Eigen::Matrix3d::Identity(), p_B.z(), {t}, 10.0, ReuseAssociation{&map, &index});
  REQUIRE(lik.has_reused());
  CHECK(lik(p_B.x(), p_B.y()) == Approx(0.0).margin(1e-6));
  // The same bearing under the other copy is as likely (the copies alias until the motion
  // tells them apart); 0.5 m off is not; 4 m off (no copy within the capture radius) is
  // an outlier, bounded.
  CHECK(lik(p_B.x() + 8.0, p_B.y()) == Approx(0.0).margin(1e-6));
  CHECK(lik(p_B.x() + 0.5, p_B.y()) < -20.0);
  const double far = lik(p_B.x() + 4.0, p_B.y() + 1.0);
  CHECK(far < -20.0);
  CHECK(std::isfinite(far));
  CHECK(lik.associate(0, p_B.x(), p_B.y()) == 0);
  CHECK(lik.associate(0, p_B.x() + 8.1, p_B.y()) == 1);
  CHECK(lik.associate(0, p_B.x() + 4.0, p_B.y() + 1.0) == -1);  // 4.1 m from both copies: beyond the 4 m capture
  // A yaw offset turns the bearing about the body: the copy is found at the turned point.
  CHECK(lik.associate(0, p_B.x(), p_B.y(), 0.2) == 0);
  // Resolved at a pose near copy 2: the term becomes copy 2 and inverts to its body pose.
  std::size_t dropped = 9;
  const ReprojectionLikelihood r = lik.resolved(8.3, -0.2, 0.0, &dropped);
  CHECK(dropped == 0);
  REQUIRE(r.size() == 1);
  CHECK_FALSE(r.has_reused());
  CHECK(r.term(0).p_LinW.x() == Approx(8.0));
  const auto inv = r.invert(0);
  REQUIRE(inv);
  CHECK((*inv - Eigen::Vector2d(8.4, -0.3)).norm() < 1e-6);
  // NaN pose: every reused term is dropped, no crash.
  CHECK(lik.resolved(std::numeric_limits<double>::quiet_NaN(), 0, 0, &dropped).size() == 0);
  CHECK(dropped == 1);
}
