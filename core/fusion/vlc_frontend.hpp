#pragma once
// The camera side of the fusion: decodes a rolling-shutter frame into LED observations and
// turns them into a position measurement once the attitude at the observation time is
// known (SEEDS.md A, S2: stripes -> frequency -> LED id -> position).
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "core/common/samples.hpp"
#include "core/filter/planar_filter.hpp"
#include "core/fusion/fusion_options.hpp"
#include "core/fusion/heading_feedback.hpp"
#include "core/fusion/reprojection_likelihood.hpp"
#include "core/vlc/camera_height.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_observation.hpp"

namespace luxloc {

struct DecodedFrame {
  TimeNs t_frame = 0;
  TimeNs t_obs = 0;     // mid-exposure of the decoded LEDs' rows (rolling shutter)
  int leds = 0;         // blobs identified
  int rejected = 0;     // blobs refused
  struct Impl;
  std::shared_ptr<const Impl> impl;  // the decoder's observations
};

// The identified LEDs of a decoded frame (for the live view's camera overlay).
const std::vector<LedObservation>& accepted_leds(const DecodedFrame& frame);

// The current estimate, for the single-hypothesis paths (EKF, loose fix, yaw) in a map that
// reuses frequencies: which copy a blob of a reused class is. sigma_m: its 1-sigma spread;
// a copy is taken only when 3 sigma stays inside the class's capture radius.
struct PoseHint {
  Eigen::Vector2d p_inW = Eigen::Vector2d::Zero();
  double yaw_offset_rad = 0.0;  // of the R_BtoW the call is given
  double sigma_m = 0.0;
};

class VlcFrontend {
 public:
  VlcFrontend(const CameraModel& camera, const LedMap& map, const FusionOptions& options, double device_height_m);
  ~VlcFrontend();
  DecodedFrame decode(const FrameSample& frame) const;
  // The frame as a global shutter at t_obs would have seen it: each LED's row was exposed at
  // its own time t_i (rolling shutter), when the body was turned by Exp(omega_inB (t_i -
  // t_obs)) against its attitude at t_obs; its centre is moved to where its bearing lies at
  // t_obs. omega_inB: the body rate (rad/s) over the frame's readout.
  DecodedFrame derotated(const DecodedFrame& frame, const Eigen::Vector3d& omega_inB) const;
  // Position of the body from the decoded LEDs, given the attitude; nullopt when the
  // frame cannot fix a position (no LED, degenerate geometry).
  // In a reuse map the blobs of reused classes need `hint` (without it only the LEDs of
  // classes of one count).
  std::optional<PositionMeasurement> fix(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                         const std::optional<PoseHint>& hint = std::nullopt) const;
  // The yaw offset of R_BtoW (true yaw - its yaw) from the camera geometry of two or more
  // LEDs: the horizontal pattern of their bearings against the map's; nullopt with fewer
  // than two LEDs or a baseline too short to tell.
  std::optional<YawMeasurement> yaw_offset(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                           const std::optional<PoseHint>& hint = std::nullopt) const;
  // Tight coupling: the per-particle reprojection likelihood of the frame's LEDs (each
  // particle associates the blobs of reused frequencies itself).
  ReprojectionLikelihood likelihood(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW) const;
  // The likelihood with every reused blob associated at `hint` (dropped where ambiguous
  // or where no copy is near); `dropped` counts those.
  ReprojectionLikelihood resolved_likelihood(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                             const std::optional<PoseHint>& hint, std::size_t* dropped = nullptr) const;
  // The map index of LED i of the frame's likelihood(), once resolved (for yaw_offset).
  const LedMap& map() const;
  // The device height the frames are weighed at (issue 16 part 3: a learnt height, when the
  // camera or the ranges estimate it; the nominal height otherwise).
  void set_device_height_m(double z_m);
  double device_height_m() const;
  // The body heights the frame's identified LEDs (of a frequency of their own, not cut by
  // the border) measure under R_BtoW (its yaw does not matter): the best pair's (two LEDs'
  // angle) and the best single LED's apparent size (only where the map gives its
  // diameter_m); z_hint_m picks a pair's root. Empty when neither applies.
  std::vector<CameraHeight> heights(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW, double z_hint_m,
                                    const CameraHeightOptions& options) const;
  bool reuses_frequencies() const;
  // Half the class's reuse distance (LedClassIndex::capture_radius): a pose known to
  // better than that names the copy.
  double capture_radius(int klass) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace luxloc
