#include <catch2/catch.hpp>

#include "core/imu/accel_calibration.hpp"

using namespace luxloc;

TEST_CASE("Accelerometer six-position solver: exact on noise-free readings, also with extra tilted ones", "[imu]") {
  const double g = 9.80665;
  const Eigen::Vector3d b(0.1, -0.2, 0.05), s(1.02, 0.97, 1.01);
  std::vector<Eigen::Vector3d> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  std::vector<Eigen::Vector3d> means;
  for (const auto& d : dirs) means.push_back(s.cwiseProduct(g * d) + b);
  AccelCalibrationResult r = solve_accel_calibration(means, g);
  CHECK((r.bias - b).norm() < 1e-9);
  CHECK((r.scale - s).norm() < 1e-9);
  CHECK(r.residual_rms_mps2 < 1e-9);
  // Tilted placements (the closed form alone would be off): Gauss-Newton still lands exactly.
  means.clear();
  for (const auto& d : dirs) means.push_back(s.cwiseProduct(g * (d + Eigen::Vector3d(0.08, -0.05, 0.06)).normalized()) + b);
  means.push_back(s.cwiseProduct(g * Eigen::Vector3d(1, 1, 1).normalized()) + b);
  r = solve_accel_calibration(means, g);
  CHECK((r.bias - b).norm() < 1e-8);
  CHECK((r.scale - s).norm() < 1e-8);
  CHECK(std::string(up_axis_name(Eigen::Vector3d(0.1, -9.7, 0.3))) == "-y");
}

TEST_CASE("Accelerometer six-position solver rejects too few or one-sided orientations", "[imu]") {
  const double g = 9.80665;
  CHECK_THROWS_WITH(solve_accel_calibration({{0, 0, g}, {0, 0, -g}}, g), Catch::Contains("needs 6"));
  std::vector<Eigen::Vector3d> up_only = {{0, 0, g}, {0, 0, -g}, {g, 0, 0}, {-g, 0, 0}, {0, g, 0}, {0, 0.7 * g, 0.7 * g}};
  CHECK_THROWS_WITH(solve_accel_calibration(up_only, g), Catch::Contains("-y"));
}
