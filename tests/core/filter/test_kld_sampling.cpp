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

TEST_CASE("KLD prefix: a drawn set keeps the shortest prefix that meets the bound of its own bins", "[filter]") {
  KldOptions o;
  o.bin_m = 0.5;
  o.min_particles = 100;
  o.max_particles = 50000;
  ParticleSet s;
  s.resize(20000);
  FastRng rng(7);
  // Uniform over 10 m x 10 m: 400 bins of 0.5 m, so the bound settles near
  // kld_particle_count(400) = 4650 particles (each prefix occupies nearly all of them).
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.x[i] = static_cast<float>(10.0 * rng.uniform());
    s.y[i] = static_cast<float>(10.0 * rng.uniform());
  }
  const std::size_t m = kld_prefix_size(s, o);
  INFO("prefix " << m << ", bound for 400 bins " << kld_particle_count(400, o));
  CHECK(m >= kld_particle_count(count_occupied_bins(s, m, o), o));
  CHECK(m < kld_particle_count(count_occupied_bins(s, m, o), o) + 256);  // the shortest, in steps of 256
  CHECK(m == Approx(kld_particle_count(400, o)).epsilon(0.06));
  // Heading bins split the same positions further: more bins, a longer prefix.
  s.heading = true;
  s.resize(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) s.yaw[i] = static_cast<float>(0.5 * rng.normal());
  o.bin_rad = 10.0 * 3.14159265358979323846 / 180.0;
  CHECK(kld_prefix_size(s, o) > m);
  // All in one bin: the minimum; a set shorter than its bound: the whole set.
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = s.y[i] = s.yaw[i] = 0.1f;
  CHECK(kld_prefix_size(s, o) == 256);  // the first step already exceeds min_particles = 100
  o.min_particles = 30000;
  CHECK(kld_prefix_size(s, o) == 20000);
}

TEST_CASE("Global search around copies: KLD sizes the set, which holds until one copy is left", "[filter]") {
  ParticleFilterOptions opt;
  opt.particles = 2000;
  opt.heading.enabled = true;
  opt.resample_every_correction = true;
  ParticleFilter pf(opt);
  // 37 copies of a class on a 60 m x 30 m floor (one every ~7 m), a bearing 1 m off.
  std::vector<Eigen::Vector2d> copies;
  for (int i = 0; i < 37; ++i) copies.emplace_back(1.0 + 7.0 * (i % 9), 1.0 + 7.0 * (i / 9));
  pf.initialize_around(copies, Eigen::Vector2d(1.0, 0.0), 0.25, 60000);
  REQUIRE(pf.localising());
  const std::size_t start = pf.size();
  INFO("search started with " << start << " particles");
  CHECK(start < 60000);  // ~37 small clusters: far fewer bins than the whole floor
  CHECK(start > 37 * 100);
  // Two copies explain the next frames (the device at copy 0 or 1, 1 m west of each), then one.
  const Eigen::Vector2d a = copies[0] - Eigen::Vector2d(1.0, 0.0), b = copies[1] - Eigen::Vector2d(1.0, 0.0);
  std::vector<std::size_t> sizes;
  for (int k = 0; k < 8; ++k) {
    pf.predict(MotionInput{0.05, {0.0, 0.0}, true});
    const auto lik = [&](double x, double y) {
      const double da = (Eigen::Vector2d(x, y) - a).squaredNorm(), db = (Eigen::Vector2d(x, y) - b).squaredNorm();
      return -(k < 4 ? std::min(da, db) : da) / (2 * 0.2 * 0.2);
    };
    REQUIRE(pf.weigh(lik));
    REQUIRE(pf.normalize_and_resample());
    sizes.push_back(pf.size());
    if (k < 4) CHECK(pf.localising());  // two copies live: still a search, whatever its size
  }
  INFO("sizes " << sizes[0] << " " << sizes[1] << " " << sizes[3] << " " << sizes.back());
  CHECK(sizes[3] == start);  // two copies live: the search keeps its set
  CHECK_FALSE(pf.localising());
  CHECK(sizes.back() == 2000);
  CHECK((pf.estimate().p - a).norm() < 0.1);
}
