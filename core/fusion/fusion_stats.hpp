#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>
#include <string>

namespace luxloc {

// What the fusion stage saw and did: printed at the end of every run.
struct FusionStats {
  std::uint64_t imu_samples = 0;
  std::uint64_t imu_rejected = 0;     // non-finite or non-increasing time
  std::uint64_t frames = 0;
  std::uint64_t frames_with_leds = 0;
  std::uint64_t leds_decoded = 0;     // blobs matched to an LED
  std::uint64_t blobs_rejected = 0;   // blobs the decoder refused to identify
  std::uint64_t vlc_fixes = 0;        // position fixes made from frames
  std::uint64_t fixes_accepted = 0;   // corrections the filter took
  std::uint64_t fixes_gated = 0;      // corrections refused by the gate
  std::uint64_t reinitializations = 0;
  std::uint64_t frames_without_attitude = 0;  // frames before the IMU aligned
  std::uint64_t other_samples = 0;    // kinds this filter does not use yet
  std::uint64_t corrections_ignored = 0;  // absolute samples past FusionOptions::absolute_for_s
  std::uint64_t poses = 0;
  std::uint64_t started_at_known_pose = 0;  // 1 when --start / session.yaml start: began the run
  // Motion model (docs/MOTION.md): its name, the steps PDR detected, and the gait
  // calibration the fixes taught the filter (step-length scale, heading offset; NaN
  // without the pedestrian model), filled in by finish().
  std::string motion;
  std::uint64_t steps = 0;
  // `--motion auto` (issue 16): the gait gate was on; the steps it let through (of `steps`
  // detected) and the seconds predicted in each regime (MotionRegime: cv, strapdown, gait,
  // still): the motion mode over time.
  bool motion_auto = false;
  std::uint64_t steps_used = 0;
  // Vertical-acceleration samples of heel-strike impacts replaced (core/imu/impact_filter.hpp).
  std::uint64_t impact_samples = 0;
  std::array<double, 4> regime_s{};
  double turning_in_place_s = 0.0;  // position held while the IMU turned (MotionSourceOptions::hold_turning_in_place)
  // The lever arm learnt from turns on the spot (MotionSourceOptions::lever_arm): forward,
  // left (m; NaN until a turn gave it) and the turns it came from.
  double lever_forward_m = std::numeric_limits<double>::quiet_NaN(), lever_left_m = std::numeric_limits<double>::quiet_NaN();
  int lever_turns = 0;
  double gait_scale = std::numeric_limits<double>::quiet_NaN();
  double gait_heading_offset_rad = std::numeric_limits<double>::quiet_NaN();
  // Heading in the fusion (core/fusion/heading_feedback.hpp): transfers of the filter's yaw
  // offset into the AHRS, the gyro z rate they taught it (rad/s), the camera yaw
  // measurements of the EKF path taken / refused, and the final fused-yaw sigma (rad).
  std::uint64_t heading_transfers = 0;
  double heading_learnt_rate_rps = 0.0;
  std::uint64_t camera_yaw_used = 0, camera_yaw_rejected = 0;
  double sigma_yaw_rad = std::numeric_limits<double>::quiet_NaN();
  // Frequency reuse (issue 14): blobs of a reused frequency (the filter chose the copy),
  // global starts (particles over the whole map: no start, no unique LED in view) and
  // global restarts after a lost track, and each global search: when it began (data
  // time, s) and how long until the particles gathered on one hypothesis (NaN: never).
  std::uint64_t reused_blobs = 0;
  std::uint64_t global_starts = 0, global_restarts = 0;
  double global_converged_s = std::numeric_limits<double>::quiet_NaN();  // the first search's
  struct GlobalSearch {
    double t_start_s = 0.0;
    double converged_after_s = std::numeric_limits<double>::quiet_NaN();
    std::size_t particles = 0;  // the set it started with (KLD-sampled, ParticleFilter::search_kld)
  };
  std::vector<GlobalSearch> global_searches;
  // Height from the camera geometry (issue 16 part 3, FusionOptions::camera_height): heights
  // measured (a frame's best LED pair and best LED size), used / gated by the height state;
  // its final value and sigma (NaN: not estimated from the camera); whether they went into
  // the UWB height filter (else the camera's own VerticalFilter).
  std::uint64_t camera_heights_used = 0, camera_heights_gated = 0, camera_height_reopened = 0;
  double final_height_m = std::numeric_limits<double>::quiet_NaN();
  double final_height_sigma_m = std::numeric_limits<double>::quiet_NaN();
  bool camera_height_in_uwb = false;
  // With the nominal height in use (no camera height, no UWB height): what the camera's
  // heights say it is (the summary warns when they disagree); NaN without any.
  std::uint64_t height_check_used = 0;
  double height_check_m = std::numeric_limits<double>::quiet_NaN();
  double height_check_sigma_m = std::numeric_limits<double>::quiet_NaN();
  double nominal_height_m = std::numeric_limits<double>::quiet_NaN();
  // Honest sigma (FusionOptions::innovation_bias): poses whose sigma_x or sigma_y carried
  // more of the fixes' persistent innovation (a filter lagging its fixes) than of the
  // filter's own spread, and the largest such term (m).
  std::uint64_t poses_lag_widened = 0;
  double max_lag_sigma_m = 0.0;
  // Outages at whose start the particles' gait was re-centred on the least-squares fit
  // (FusionOptions::gait_regression), and the largest change of the step-length scale.
  std::uint64_t gait_recentred = 0;
  double max_gait_recentre_scale = 0.0;
  // First corrections after an outage before which the yaw offsets were shuffled
  // (FusionOptions::decouple_heading_after_outage).
  std::uint64_t headings_decoupled = 0;
};

}  // namespace luxloc
