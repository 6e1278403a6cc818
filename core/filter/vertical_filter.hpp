#pragma once
// The device height for a platform that flies or changes height, observed by the camera
// geometry (issue 16 part 3; core/vlc/camera_height.hpp) when no UWB height filter carries
// z (with one, the camera's heights go into that filter's z instead: one height state):
//   state   [z, v_z], constant velocity with white acceleration (psd q)
//   measure z_meas = z + n, n ~ N(0, sigma^2), gated at gate_sigma
// The planar filters stay 2-D (core/filter/particle_set.hpp); they are weighed at this z.
#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct VerticalFilterOptions {
  // Vertical white-acceleration psd, (m/s^2)^2/Hz: the UWB height filter's value
  // (HeightBiasOptions::vertical_accel_psd, chosen on sim drone seeds 1-10); checked for the
  // camera on drone seeds 1-5 with --camera (docs/PLATFORMS.md "Height from the camera").
  double accel_psd = 0.1;
  // Prior around the nominal height: 0.5 m covers a drone's 0.5-1.7 m around 1.1 m.
  double height_sigma0_m = 0.5;
  double speed_sigma0_mps = 0.5;
  // Innovations beyond this many sigma are not used (a wrong LED pair, a blob of two LEDs).
  double gate_sigma = 3.0;
  // After this many gated heights in a row the state is wrong, not the camera (every pair
  // of every frame disagrees): the height's variance reopens to its prior and the
  // measurement is used (as HeightBiasOptions::short_run_reopen; 5 frames: 0.17 s at 30 fps).
  int reopen_after_gated = 5;
  double min_height_m = -1.0, max_height_m = 10.0;  // z is kept in this span
};

struct VerticalFilterStats {
  std::uint64_t used = 0, gated = 0, reopened = 0;
};

class VerticalFilter {
 public:
  VerticalFilter(const VerticalFilterOptions& options, double nominal_height_m);
  // Moves the state to t (the first call only sets the time; older t: no-op).
  void predict(TimeNs t);
  enum class Outcome { used, gated, skipped };
  Outcome update(TimeNs t, double z_m, double sigma_m);
  double height_m() const { return x_(0); }
  double height_sigma_m() const { return std::sqrt(std::max(0.0, P_(0, 0))); }
  double vertical_speed_mps() const { return x_(1); }
  const VerticalFilterStats& stats() const { return stats_; }

 private:
  VerticalFilterOptions options_;
  Eigen::Vector2d x_;
  Eigen::Matrix2d P_;
  std::optional<TimeNs> t_;
  int gated_run_ = 0;
  VerticalFilterStats stats_;
};

}  // namespace luxloc
