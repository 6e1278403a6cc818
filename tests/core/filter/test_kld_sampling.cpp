#include <catch2/catch.hpp>
#include <cmath>
#include <numeric>

#include "core/filter/fast_rng.hpp"
#include "core/filter/kld_sampling.hpp"
#include "core/filter/particle_filter.hpp"

using namespace luxloc;

TEST_CASE("KLD bound matches Fox's formula and is clamped", "[filter]") {
  KldOptions o;
  o.epsilon = 0.05;
  o.z = 2.326;
  o.min_particles = 10;
  o.max_particles = 1'000'000;
  // k = 101: (100 / 0.1) * (1 - 2/900 + sqrt(2/900) * 2.326)^3 = 1358.1
  const double a = 2.0 / 900.0;
  const double expect = 1000.0 * std::pow(1.0 - a + std::sqrt(a) * 2.326, 3);
  REQUIRE(expect == Approx(1358.1).margin(0.1));
  REQUIRE(kld_particle_count(101, o) == static_cast<std::size_t>(std::ceil(expect)));
  REQUIRE(kld_particle_count(1, o) == 10);
  REQUIRE(kld_particle_count(0, o) == 10);
  REQUIRE(kld_particle_count(1000, o) > kld_particle_count(100, o));
  o.max_particles = 500;
  REQUIRE(kld_particle_count(101, o) == 500);
}

TEST_CASE("Occupied bins are counted per cell, repeats once", "[filter]") {
  ParticleSet s;
  s.resize(6);
  const float xs[] = {0.01f, 0.02f, 0.06f, -0.01f, 0.01f, 0.01f};
  const float ys[] = {0.0f, 0.04f, 0.0f, 0.0f, 0.0f, 0.0f};
  const float vx[] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f};
  for (int i = 0; i < 6; ++i) {
    s.x[i] = xs[i];
    s.y[i] = ys[i];
    s.vx[i] = vx[i];
    s.vy[i] = 0.0f;
  }
  KldOptions o;
  o.bin_m = 0.05;
  std::vector<std::uint32_t> all = {0, 1, 2, 3, 4, 5, 0, 0};
  REQUIRE(count_occupied_bins(s, all, o) == 3);  // [0,0.05), [0.05,0.1), [-0.05,0) in x
  o.bin_mps = 0.5;
  REQUIRE(count_occupied_bins(s, all, o) == 4);  // particle 5 moves
  REQUIRE(count_occupied_bins(s, std::vector<std::uint32_t>{0, 1, 4}, o) == 1);
}

TEST_CASE("KLD-sampling shrinks a converged filter and grows a spread one", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 5000;
  opt.kld.enabled = true;
  opt.kld.min_particles = 300;
  opt.kld.max_particles = 20000;
  opt.resample_every_correction = true;
  ParticleFilter pf(opt);
  FastRng noise(2);
  pf.initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.01);
  for (int k = 0; k < 60; ++k) {  // converged on 2 cm fixes of a still device
    pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
    PositionMeasurement m;
    m.z = 0.02 * Eigen::Vector2d(noise.normal(), noise.normal());
    m.R = Eigen::Matrix2d::Identity() * 0.0004;
    pf.correct(m);
  }
  const std::size_t converged = pf.size();
  INFO("converged: " << converged << " particles");
  REQUIRE(converged < 1000);
  REQUIRE(converged >= 300);
  REQUIRE(pf.estimate().p.norm() < 0.05);
  // Spread: a wide prior and a weak (2 m) fix keep many bins occupied.
  pf.initialize({0, 0}, Eigen::Matrix2d::Identity() * 4.0);
  for (int k = 0; k < 5; ++k) {
    pf.predict(MotionInput{1.0 / 30, {0, 0}, false});
    PositionMeasurement m;
    m.R = Eigen::Matrix2d::Identity() * 4.0;
    pf.correct(m);
  }
  INFO("spread: " << pf.size() << " particles");
  REQUIRE(pf.size() > 3 * converged);
  REQUIRE(pf.size() <= 20000);
}
