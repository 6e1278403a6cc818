#pragma once
// How the fusion uses downward-camera visual odometry (`luxloc run --vo`): each frame's
// floor motion (FloorOdometry), rotated into the world with the attitude's yaw, is a
// velocity measurement for the filter (SEEDS.md C.6's vision observation).
#include <cstdint>

#include "core/vo/floor_odometry.hpp"

namespace luxloc {

struct VoOptions {
  bool enabled = false;
  FloorOdometryOptions odometry;
  double velocity_sigma_mps = 0.05;  // 1 sigma of a frame-to-frame velocity
  double max_scale_error = 0.1;      // |k - 1| beyond this: the floor model does not hold, skip
  // Heading of the displacement: the attitude filter's yaw at the first motion, then the
  // visual yaw increments integrated (the floor's rotation is measured far more precisely
  // than the magnetometer-referenced yaw, which turns disturb), pulled towards the attitude
  // yaw with this time constant (s); 0: never pulled. A tiny value follows the attitude yaw.
  double heading_tau_s = 0.0;
};

struct VoStats {
  std::uint64_t frames = 0;
  std::uint64_t motions = 0;   // frame pairs with a fitted similarity
  std::uint64_t accepted = 0;  // velocity updates the filter took
  std::uint64_t rejected = 0;  // gated by the filter or bad scale
};

}  // namespace luxloc
