#pragma once
// Where an LED is, from many bearing rays towards it (camera centre + direction in the
// world, one per sighting from a known pose): the least-squares point closest to all rays,
// sum_i |(I - d_i d_i^T)(X - o_i)|^2 -> a 3x3 linear system, or with the height known (a
// ceiling) the 2x2 system on the rays' crossings of that plane. Outlying rays (a wrong
// pose, a mis-centred blob) are down-weighted by iterated Huber reweighting.
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace luxloc {

struct BearingRay {
  Eigen::Vector3d origin_inW = Eigen::Vector3d::Zero();
  Eigen::Vector3d dir_inW = Eigen::Vector3d::UnitZ();  // unit
};

struct TriangulationOptions {
  std::optional<double> fixed_z;  // the LED's height when known
  double huber_m = 0.02;          // residuals beyond this count linearly
  int iterations = 5;
  // Rays this close to parallel (smallest eigenvalue of the normal matrix per ray) leave
  // the point undetermined along them: refused.
  double min_conditioning = 1e-4;
};

struct TriangulatedPoint {
  bool ok = false;
  Eigen::Vector3d p_inW = Eigen::Vector3d::Zero();
  double rms_m = 0.0;  // rms distance of the rays from the point
  std::size_t rays = 0;
};

TriangulatedPoint triangulate(const std::vector<BearingRay>& rays, const TriangulationOptions& options = {});

}  // namespace luxloc
