// The Gaussian-smoothed closed path: exact derivatives, periodicity, straight segments kept,
// rounded corners.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "core/sim/smooth_path.hpp"

using namespace luxloc::sim;

namespace {
const std::vector<Eigen::Vector2d> kLoop{{1, 1}, {7, 1}, {7, 5}, {5, 5}, {5, 3}, {3, 3}, {3, 5}, {1, 5}};
}

TEST_CASE("SmoothPath derivatives agree with finite differences", "[sim]") {
  const SmoothPath path(kLoop, 0.5);
  CHECK(path.length() == Approx(24.0));
  const double h = 1e-4;
  for (double u = -3.0; u < 27.0; u += 0.37) {
    const PathPoint p = path.at(u), a = path.at(u - h), b = path.at(u + h);
    INFO("u " << u);
    CHECK((p.c1 - (b.c - a.c) / (2 * h)).norm() < 1e-6);
    CHECK((p.c2 - (b.c1 - a.c1) / (2 * h)).norm() < 1e-5);
    CHECK((p.c3 - (b.c2 - a.c2) / (2 * h)).norm() < 1e-4);
    // Periodic.
    CHECK((path.at(u + path.length()).c - p.c).norm() < 1e-9);
  }
}

TEST_CASE("SmoothPath keeps straights and rounds corners", "[sim]") {
  const SmoothPath path(kLoop, 0.5);
  // Middle of the 6 m first segment, 3 m (6 sigma) from the corners: the polygon itself.
  const PathPoint mid = path.at(3.0);
  CHECK((mid.c - Eigen::Vector2d(4, 1)).norm() < 1e-6);
  CHECK(mid.c1.norm() == Approx(1.0).margin(1e-6));
  CHECK(mid.c2.norm() < 1e-6);
  // At the 90 deg corner (7, 1): the tangent is the mean of both directions (|c1| = cos 45),
  // the curve cuts inside the corner, and the turn radius stays walkable.
  const PathPoint corner = path.at(6.0);
  CHECK(corner.c1.norm() == Approx(std::sqrt(0.5)).margin(1e-3));
  CHECK(corner.c.x() < 7.0);
  CHECK(corner.c.y() > 1.0);
  double min_radius = 1e9;
  for (double u = 0.0; u < path.length(); u += 0.01) {
    const PathPoint p = path.at(u);
    const double kappa = std::abs(p.c1.x() * p.c2.y() - p.c1.y() * p.c2.x()) / std::pow(p.c1.norm(), 3);
    min_radius = std::min(min_radius, 1.0 / kappa);
    // Never further than ~0.5 m from the polygon, never outside the polygon's bounding box.
    CHECK(p.c.x() >= 1.0 - 1e-9);
    CHECK(p.c.x() <= 7.0 + 1e-9);
  }
  CHECK(min_radius > 0.3);
  CHECK(min_radius < 1.0);
}

TEST_CASE("SmoothPath rejects unusable polygons", "[sim]") {
  CHECK_THROWS_AS(SmoothPath({{0, 0}, {1, 0}}, 0.5), std::invalid_argument);
  CHECK_THROWS_AS(SmoothPath({{0, 0}, {4, 0}, {4, 0}, {0, 4}}, 0.5), std::invalid_argument);
  CHECK_THROWS_AS(SmoothPath({{0, 0}, {4, 0}, {0, 0.01}}, 0.5), std::invalid_argument);  // U-turn
  CHECK_THROWS_AS(SmoothPath({{0, 0}, {1, 0}, {0, 1}}, 0.5), std::invalid_argument);    // < 8 sigma
}
