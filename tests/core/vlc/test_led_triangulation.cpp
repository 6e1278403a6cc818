// Least-squares LED position from bearing rays: exact on clean rays, robust to a wrong ray,
// with or without a known height; parallel rays are refused.
#include <catch2/catch.hpp>
#include <random>

#include "core/vlc/led_triangulation.hpp"

using namespace luxloc;

namespace {

std::vector<BearingRay> rays_to(const Eigen::Vector3d& led, int n, double noise_rad, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nz(0.0, noise_rad);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<BearingRay> rays;
  for (int i = 0; i < n; ++i) {
    BearingRay r;
    r.origin_inW = led + Eigen::Vector3d(u(rng), u(rng), -2.0);  // a camera ~2 m below
    Eigen::Vector3d d = (led - r.origin_inW).normalized();
    d += Eigen::Vector3d(nz(rng), nz(rng), nz(rng));
    r.dir_inW = d.normalized();
    rays.push_back(r);
  }
  return rays;
}

}  // namespace

TEST_CASE("triangulate: clean rays give the point, noise averages out", "[vlc]") {
  const Eigen::Vector3d led(3.0, 5.0, 3.0);
  const TriangulatedPoint exact = triangulate(rays_to(led, 20, 0.0, 1));
  REQUIRE(exact.ok);
  CHECK((exact.p_inW - led).norm() < 1e-9);
  CHECK(exact.rms_m < 1e-9);
  // 5 mrad per axis, two axes across the ray, ~2.2 m away: ~1.6 cm rms off the point.
  const TriangulatedPoint noisy = triangulate(rays_to(led, 300, 0.005, 2));
  REQUIRE(noisy.ok);
  CHECK((noisy.p_inW - led).norm() < 0.02);
  CHECK(noisy.rms_m == Approx(0.016).epsilon(0.25));
}

TEST_CASE("triangulate: a wrong ray is down-weighted, known height, parallel rays refused", "[vlc]") {
  const Eigen::Vector3d led(1.0, 1.0, 2.9);
  std::vector<BearingRay> rays = rays_to(led, 30, 0.002, 3);
  BearingRay wrong;
  wrong.origin_inW = {0, 0, 1};
  wrong.dir_inW = Eigen::Vector3d(1, 0, 0.3).normalized();  // points far away from the LED
  rays.push_back(wrong);
  TriangulationOptions plain;
  plain.iterations = 1;  // least squares alone: pulled by the outlier
  const double err_plain = (triangulate(rays, plain).p_inW - led).norm();
  const TriangulatedPoint robust = triangulate(rays);
  REQUIRE(robust.ok);
  CHECK((robust.p_inW - led).norm() < 0.01);
  CHECK((robust.p_inW - led).norm() < err_plain);
  TriangulationOptions z;
  z.fixed_z = 2.9;
  const TriangulatedPoint on_plane = triangulate(rays, z);
  REQUIRE(on_plane.ok);
  CHECK(on_plane.p_inW.z() == 2.9);
  CHECK((on_plane.p_inW - led).norm() < 0.01);
  // All rays along one line: depth undetermined.
  std::vector<BearingRay> parallel(5);
  for (int i = 0; i < 5; ++i) parallel[static_cast<std::size_t>(i)].origin_inW = {0, 0, -i * 0.1};
  CHECK_FALSE(triangulate(parallel).ok);
  CHECK_FALSE(triangulate({}).ok);
}
