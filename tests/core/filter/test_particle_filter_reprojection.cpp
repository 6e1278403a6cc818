// The per-particle weighing of the tight coupling (issue 14's bench): the likelihood's hot
// path (cached intrinsics, inlined projection, polynomial turn for small yaw offsets) must
// give what the camera model and libm give, and the particle filter weighs with it.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/filter/particle_filter.hpp"
#include "core/fusion/reprojection_likelihood.hpp"
#include "core/sim/scenario.hpp"

using namespace luxloc;

namespace {

// The likelihood's model, written out with CameraModel::project and std::cos / std::sin.
double reference(const CameraModel& cam, const std::vector<ReprojectionTerm>& terms, double z_B, double outlier_px,
                 double x, double y, double e) {
  const Eigen::Matrix3d M = cam.R_CtoB.transpose();
  const Eigen::Vector3d offset = cam.R_CtoB.transpose() * cam.p_CinB;
  const double o2 = outlier_px * outlier_px, c = std::cos(e), s = std::sin(e);
  double ll = 0.0;
  for (const ReprojectionTerm& t : terms) {
    const Eigen::Vector3d d = t.p_LinW - Eigen::Vector3d(x, y, z_B);
    Eigen::Vector2d uv;
    if (!cam.project(M * Eigen::Vector3d(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()) - offset, uv)) {
      ll -= 0.5 * o2 * t.inv_var;
      continue;
    }
    const double e2 = (uv - t.uv).squaredNorm();
    ll -= 0.5 * t.inv_var * (e2 < o2 ? e2 : o2 * (1.0 + std::log(e2 / o2)));
  }
  return ll;
}

}  // namespace

TEST_CASE("Reprojection weighing fast path agrees with the camera model and libm, small and large yaw offsets", "[filter][reprojection]") {
  CameraModel cam = sim::default_sim_camera();
  cam.dist = {-0.05, 0.01, 0.001, -0.002, 0.003};  // every distortion term in play
  std::vector<ReprojectionTerm> terms;
  terms.push_back({Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector2d(300, 200), 0.25, -1});
  terms.push_back({Eigen::Vector3d(2.5, 1.0, 3.0), Eigen::Vector2d(420, 260), 0.25, -1});
  terms.push_back({Eigen::Vector3d(0.0, 0.0, 0.5), Eigen::Vector2d(320, 240), 0.25, -1});  // below the camera
  const double z_B = 1.0, outlier = 10.0;
  const ReprojectionLikelihood lik(cam, Eigen::Matrix3d::Identity(), z_B, terms, outlier);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(0.0, 3.0), ue(-0.3, 0.3);
  for (int q = 0; q < 500; ++q) {
    const double x = ux(rng), y = ux(rng), e = q % 5 == 0 ? 4.0 * ue(rng) : ue(rng);  // some beyond 0.25 rad
    const double want = reference(cam, terms, z_B, outlier, x, y, e);
    REQUIRE(lik(x, y, e) == Approx(want).epsilon(1e-12).margin(1e-9));
  }
  // No distortion: the same.
  cam.dist = {0, 0, 0, 0, 0};
  const ReprojectionLikelihood plain(cam, Eigen::Matrix3d::Identity(), z_B, terms, outlier);
  for (int q = 0; q < 100; ++q) {
    const double x = ux(rng), y = ux(rng), e = ue(rng);
    REQUIRE(plain(x, y, e) == Approx(reference(cam, terms, z_B, outlier, x, y, e)).epsilon(1e-12).margin(1e-9));
  }
}

TEST_CASE("Particle filter weighs with a reprojection likelihood and follows its LED", "[filter][reprojection]") {
  const CameraModel cam = sim::default_sim_camera();
  const Eigen::Vector3d p_L(2.0, 1.0, 3.0), p_B(2.3, 0.8, 1.0);
  Eigen::Vector2d uv;
  REQUIRE(cam.project(cam.R_CtoB.transpose() * (p_L - p_B), uv));
  ParticleFilterOptions opt;
  opt.particles = 20000;
  opt.resample_every_correction = true;
  ParticleFilter pf(opt);
  pf.initialize({2.0, 1.0}, Eigen::Matrix2d::Identity() * 0.25);
  const ReprojectionLikelihood lik(cam, Eigen::Matrix3d::Identity(), p_B.z(), {{p_L, uv, 1.0, -1}}, 10.0);
  for (int k = 0; k < 5; ++k) {
    REQUIRE(pf.weigh(lik));
    REQUIRE(pf.normalize_and_resample());
  }
  // One LED fixes the position (the yaw offsets are small, the attitude level).
  CHECK((pf.estimate().p - p_B.head<2>()).norm() < 0.05);
}

TEST_CASE("Reprojection block path (eight particles at a time, single precision) agrees with operator()", "[filter][reprojection]") {
  CameraModel cam = sim::default_sim_camera();
  cam.dist = {-0.05, 0.01, 0.001, -0.002, 0.003};
  // A reuse floor: 1000 Hz at x = 0, 8, 16 (8 m reuse), 1600 Hz at (4, 5), one 2200 Hz LED.
  std::vector<Led> leds;
  const auto add = [&](int id, double f, double x, double y) {
    Led l;
    l.id = id;
    l.freq_hz = f;
    l.p_inW = {x, y, 3.0};
    leds.push_back(l);
  };
  add(1, 1000, 0, 0);
  add(2, 1000, 8, 0);
  add(3, 1000, 16, 0);
  add(4, 1600, 4, 5);
  add(5, 1600, 12, 5);
  add(6, 2200, 6, 2);
  const LedMap map(std::move(leds), "m");
  const LedClassIndex index(map);
  const double z_B = 1.0, ox = 7.3, oy = -0.4;  // particles relative to an origin, as the filter keeps them
  std::vector<ReprojectionTerm> terms;
  terms.push_back({Eigen::Vector3d::Zero(), Eigen::Vector2d(330, 250), 0.25, map.class_of(0)});  // reused
  terms.push_back({Eigen::Vector3d::Zero(), Eigen::Vector2d(200, 100), 0.25, map.class_of(3)});  // reused
  terms.push_back({map.leds()[5].p_inW, Eigen::Vector2d(420, 300), 0.5, -1});                    // known
  terms.push_back({Eigen::Vector3d::Zero(), Eigen::Vector2d(320, 470), 0.25, map.class_of(0)});  // steep ray
  const ReprojectionLikelihood lik(cam, Eigen::Matrix3d::Identity(), z_B, terms, 10.0, ReuseAssociation{&map, &index});
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> ux(-9.0, 10.0), uy(-3.0, 6.0), ue(-0.2, 0.2);
  const std::size_t n = 1003;  // not a multiple of eight
  std::vector<float> x(n), y(n), e(n), out(n);
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = static_cast<float>(ux(rng));
    y[k] = static_cast<float>(uy(rng));
    e[k] = static_cast<float>(k % 7 == 0 ? 2.0 * ue(rng) + 0.3 : ue(rng));  // some beyond 0.25 rad
  }
  lik.log_likelihood_block(ox, oy, x.data(), y.data(), e.data(), n, out.data());
  std::size_t differ = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double want = lik(ox + x[k], oy + y[k], e[k]);
    const double err = std::abs(out[k] - want) / std::max(1.0, std::abs(want));
    if (err > 1e-4) ++differ;  // an association at a capture boundary
    else worst = std::max(worst, err);
  }
  INFO("worst relative error " << worst << ", " << differ << " differ");
  CHECK(differ <= 2);
  CHECK(worst < 1e-4);
  // Without yaw offsets (e null) the same as e = 0.
  lik.log_likelihood_block(ox, oy, x.data(), y.data(), nullptr, n, out.data());
  for (std::size_t k = 0; k < n; k += 17) CHECK(out[k] == Approx(lik(ox + x[k], oy + y[k], 0.0)).epsilon(1e-4).margin(1e-3));
}
