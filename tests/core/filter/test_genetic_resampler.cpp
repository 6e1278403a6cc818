#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <utility>

#include "core/filter/fast_rng.hpp"
#include "core/filter/filter_factory.hpp"
#include "core/filter/genetic_resampler.hpp"

using namespace luxloc;

namespace {

ParticleSet line_of_particles(std::size_t n) {
  ParticleSet s;
  s.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x[i] = static_cast<float>(i);
    s.y[i] = -static_cast<float>(i);
    s.vx[i] = 0.1f * static_cast<float>(i);
    s.vy[i] = 0.0f;
  }
  return s;
}

}  // namespace

TEST_CASE("Genetic resampling keeps the excellent particles and crosses the decayed ones", "[filter]") {
  const std::size_t n = GENERATE(std::size_t{200}, std::size_t{20000});  // one chunk, several (parallel)
  ParticleSet s = line_of_particles(n);
  const ParticleSet before = s;
  // Every 5th particle is excellent: log weight 0 (max) or log(0.7) (>= 0.65 relative);
  // the rest have relative weight 0.5 or 1e-6: decayed.
  FloatVector log_w(n);
  std::set<std::pair<float, float>> excellent;
  for (std::size_t i = 0; i < n; ++i) {
    log_w[i] = i % 5 == 0 ? (i % 10 == 0 ? 0.0f : std::log(0.7f)) : (i % 2 ? std::log(0.5f) : std::log(1e-6f));
    if (i % 5 == 0) excellent.insert({before.x[i], before.y[i]});
  }
  GeneticOptions o;
  o.mutation_probability = 0.0;  // crossover only: positions can be checked exactly
  const GeneticStats st = genetic_resample(s, log_w, 0.0f, o, 7, 1);
  REQUIRE(st.excellent == (n + 4) / 5);
  REQUIRE(st.decayed == n - st.excellent);
  REQUIRE(st.mutated == 0);
  std::size_t partners_hit = 0;
  std::set<std::pair<float, float>> partners;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 5 == 0) {  // excellent: untouched
      REQUIRE(s.x[i] == before.x[i]);
      REQUIRE(s.vx[i] == before.vx[i]);
      continue;
    }
    // B.5b: x' = 0.7 x_e + 0.3 x_d -> recover x_e and check it is an excellent particle,
    // the same one for every state component.
    const float xe = (s.x[i] - 0.3f * before.x[i]) / 0.7f;
    const float ye = (s.y[i] - 0.3f * before.y[i]) / 0.7f;
    const float vxe = (s.vx[i] - 0.3f * before.vx[i]) / 0.7f;
    const float j = std::round(xe);
    REQUIRE(xe == Approx(j).margin(1e-2 * (1 + j * 1e-3)));
    REQUIRE(ye == Approx(-j).margin(1e-2 * (1 + j * 1e-3)));
    REQUIRE(vxe == Approx(0.1 * j).margin(1e-3 * (1 + j * 1e-3)));
    REQUIRE(excellent.count({j, -j}) == 1);
    partners.insert({j, -j});
    ++partners_hit;
  }
  REQUIRE(partners_hit == st.decayed);
  REQUIRE(partners.size() > excellent.size() / 2);  // partners are drawn, not one favourite
}

TEST_CASE("Genetic resampling draws partners in proportion to their weights and mutates with p", "[filter]") {
  const std::size_t n = 20000;
  ParticleSet s;
  s.resize(n);
  FloatVector log_w(n, std::log(1e-3f));
  // Two excellent particles, weights 1 and 0.7, at x = 0 and x = 100.
  log_w[0] = 0.0f;
  log_w[1] = std::log(0.7f);
  s.x[1] = 100.0f;
  GeneticOptions o;
  o.alpha = 1.0;  // a decayed particle becomes a copy of its partner (+ mutation)
  o.mutation_position_m = 0.01;
  o.mutation_velocity_mps = 0.0;
  const GeneticStats st = genetic_resample(s, log_w, 0.0f, o, 3, 4);
  REQUIRE(st.excellent == 2);
  std::size_t to_second = 0, mutated = 0;
  for (std::size_t i = 2; i < n; ++i) {
    to_second += s.x[i] > 50.0f;
    mutated += s.y[i] != 0.0f;
    REQUIRE(std::abs(s.y[i]) < 0.01 * 6);  // r_k * scale * normal
  }
  const double frac = static_cast<double>(to_second) / static_cast<double>(n - 2);
  REQUIRE(frac == Approx(0.7 / 1.7).margin(0.02));
  REQUIRE(static_cast<double>(mutated) / static_cast<double>(n - 2) == Approx(0.5).margin(0.02));
  REQUIRE(st.mutated == mutated);
  REQUIRE(st.r_k >= 0.0);
  REQUIRE(st.r_k < 1.0);
}

TEST_CASE("Genetic PF keeps more distinct particles than systematic resampling and still tracks", "[filter]") {
  // Sparse fixes (1 Hz, 20 cm) on a slowly walking device, resampling at every fix, no
  // roughening: plain resampling keeps only copies of the surviving particles
  // (impoverishment, SEEDS.md B); the genetic operators keep the set diverse.
  const auto run = [](const std::string& name, std::size_t& unique_after, double& rmse) {
    FilterSettings s;
    s.name = name;
    s.pf.particles = 2000;
    s.pf.roughening_m = 0.0;
    s.pf.accel_noise_psd = 0.01;
    s.pf.resample_every_correction = true;
    auto f = make_planar_filter(s);
    auto* pf = dynamic_cast<ParticleFilter*>(f.get());
    REQUIRE(pf);
    FastRng noise(5);
    f->initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.04);
    double se = 0.0;
    std::size_t unique_sum = 0;
    int fixes = 0;
    for (int k = 1; k <= 60 * 100; ++k) {  // 60 s at 100 Hz
      const double t = k * 0.01;
      f->predict(MotionInput{0.01, {0, 0}, false});
      if (k % 100 != 0) continue;
      PositionMeasurement m;
      m.z = Eigen::Vector2d(0.2 * t, 0.0) + 0.2 * Eigen::Vector2d(noise.normal(), noise.normal());
      m.R = Eigen::Matrix2d::Identity() * 0.04;
      f->correct(m);
      std::set<std::pair<float, float>> u;
      for (std::size_t i = 0; i < pf->size(); ++i) u.insert({pf->particles().x[i], pf->particles().y[i]});
      if (t > 10) {
        unique_sum += u.size();
        ++fixes;
        se += (f->estimate().p - Eigen::Vector2d(0.2 * t, 0.0)).squaredNorm();
      }
    }
    unique_after = unique_sum / static_cast<std::size_t>(fixes);
    rmse = std::sqrt(se / fixes);
  };
  std::size_t unique_sir = 0, unique_gpf = 0;
  double err_sir = 0, err_gpf = 0;
  run("pf", unique_sir, err_sir);
  run("gpf", unique_gpf, err_gpf);
  INFO("distinct particles after resampling: SIR " << unique_sir << ", genetic " << unique_gpf
       << "; RMSE SIR " << err_sir << " m, genetic " << err_gpf << " m");
  REQUIRE(unique_gpf > 1900);
  REQUIRE(unique_sir < 1400);
  // Both track (20 cm fixes once a second); the genetic set is no worse for its diversity.
  REQUIRE(err_gpf < 0.3);
  REQUIRE(err_sir < 0.3);
  REQUIRE(err_gpf < 1.2 * err_sir);
}

TEST_CASE("Genetic PF keeps the posterior's spread: its sigma covers its error", "[filter][sigma]") {
  // The same sparse-fix tracking. The seed's genetic step pulls decayed particles 70 % of
  // the way to excellent ones and weighs all equally: the spread shrinks at every fix and
  // the filter believes itself. GeneticOptions::preserve_spread gives the set the weighted
  // posterior's mean and covariance back after each step.
  const auto run = [](bool preserve, double& inside, double& rmse, double& sigma) {
    FilterSettings s;
    s.name = "gpf";
    s.pf.particles = 2000;
    s.pf.roughening_m = 0.0;
    s.pf.accel_noise_psd = 0.05;
    s.pf.resample_every_correction = true;
    s.pf.genetic.preserve_spread = preserve;
    auto f = make_planar_filter(s);
    FastRng noise(9), walk(13);
    f->initialize({0, 0}, Eigen::Matrix2d::Identity() * 0.04);
    Eigen::Vector2d truth(0, 0), v(0.3, 0.0);
    int n = 0, in = 0;
    double se = 0.0, ss = 0.0;
    for (int k = 1; k <= 120 * 100; ++k) {  // 120 s at 100 Hz; the device turns slowly
      v = Eigen::Rotation2Dd(0.002 * walk.normal()) * v;
      truth += 0.01 * v;
      f->predict(MotionInput{0.01, {0, 0}, false});
      if (k % 100 != 0) continue;
      PositionMeasurement m;
      m.z = truth + 0.3 * Eigen::Vector2d(noise.normal(), noise.normal());
      m.R = Eigen::Matrix2d::Identity() * 0.09;
      f->correct(m);
      if (k < 1000) continue;
      const PlanarEstimate e = f->estimate();
      const Eigen::Vector2d d = e.p - truth;
      in += d.dot(e.cov_p.inverse() * d) <= 5.991;
      se += d.squaredNorm();
      ss += std::sqrt(0.5 * e.cov_p.trace());
      ++n;
    }
    inside = static_cast<double>(in) / n;
    rmse = std::sqrt(se / n);
    sigma = ss / n;
  };
  double in_seed = 0, err_seed = 0, sig_seed = 0, in_kept = 0, err_kept = 0, sig_kept = 0;
  run(false, in_seed, err_seed, sig_seed);
  run(true, in_kept, err_kept, sig_kept);
  WARN("within the 95 % ellipse: as published " << 100 * in_seed << " % (sigma " << sig_seed << " m, RMSE " << err_seed
                                                << " m), spread kept " << 100 * in_kept << " % (sigma " << sig_kept
                                                << " m, RMSE " << err_kept << " m)");
  CHECK(in_kept >= 0.85);
  CHECK(in_kept > in_seed + 0.1);
  CHECK(err_kept <= 1.1 * err_seed);  // no worse a track for it
}
