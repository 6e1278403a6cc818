#pragma once
#include <limits>
#include <optional>
#include <string>

#include "core/common/session_config.hpp"
#include "core/filter/particle_filter.hpp"
#include "core/filter/vertical_filter.hpp"
#include "core/fusion/heading_feedback.hpp"
#include "core/fusion/gait_regression.hpp"
#include "core/fusion/innovation_bias.hpp"
#include "core/fusion/motion_source.hpp"
#include "core/vlc/camera_height.hpp"
#include "core/imu/imu_calibration.hpp"
#include "core/imu/mahony_filter.hpp"

namespace luxloc {

// Everything `luxloc run` can tune about the fusion, with defaults that work on the
// simulator's walk and the spec-sample session (README "Tuning").
struct FusionOptions {
  std::string filter = "pf";  // see filter_names(): pf = seed A's SIR particle filter
  // Which inputs the fusion uses (for comparisons: imu-only, fixes-only...).
  bool use_imu = true;    // false: IMU only gives the attitude; prediction is constant velocity
  bool use_vlc = true;    // camera frames
  bool use_fixes = true;  // fixes.csv
  // Absolute corrections (VLC, fixes) are used only for this long after the filter first
  // initialised; later ones are ignored (counted). A few seconds: IMU-only dead reckoning from
  // a converged start (`luxloc compare`'s imu-only row). Infinite: always.
  double absolute_for_s = std::numeric_limits<double>::infinity();
  ParticleFilterOptions pf;
  MahonyOptions ahrs;
  // Nominal device height above the floor (m); NaN: take session.yaml's device_height_m.
  double device_height_m = std::numeric_limits<double>::quiet_NaN();
  // Motion model of the prediction (`--motion`, docs/MOTION.md): pdr (default: steps,
  // step length, attitude heading, calibrated gait), strapdown, cv; and the PDR settings.
  // The filters' process noise: pf.accel_noise_psd / velocity_tau_s (strapdown, cv) and
  // pf.gait (pdr); the EKF takes the same values.
  MotionSourceOptions motion;
  // Use the accelerometer in the motion model; false: constant velocity whatever `motion`.
  bool use_accelerometer = true;
  // Applied to every IMU sample before anything else (`--imu-calib`, `luxloc calib imu`).
  ImuCalibration imu_calibration;
  // Tight coupling: weigh particles by the reprojection error of each decoded LED (one
  // LED suffices); false: seed A's loose coupling (a position fix per frame).
  bool tight_coupling = true;
  // Tight-coupling gate: mean reprojection error (in metres at the ceiling) tolerated
  // beyond 3 sigma of the filter's spread.
  double tight_gate_m = 0.5;
  // Remove omega x v from the accelerometer before it serves as the gravity reference.
  bool compensate_centripetal = true;
  // A known start (`--start`; else session.yaml's `start:`): the filter starts there at the
  // first aligned IMU sample, without waiting for an absolute source.
  std::optional<StartPose> start;
  double start_sigma_m = std::numeric_limits<double>::quiet_NaN();  // NaN: the start's own sigma_m
  // Heading in the fusion (issue 11): the filters' yaw offset (pf.heading; the EKF path's
  // HeadingObserver takes the same noise) and its transfer into the AHRS.
  HeadingFeedbackOptions heading_feedback;
  // While the AHRS's magnetometer corrects the heading, its yaw cannot drift further than
  // the field's own error (2-3 deg): the drift clock of the yaw offset stops at this many
  // seconds (0.2 deg/s x 10 s = 2 deg, HeadingNoise::bias_sigma_rps).
  double mag_bounded_drift_s = 10.0;
  // Global localisation in a map that reuses frequencies (issue 14): with no start and no
  // LED of a frequency of its own in view, the particle filter starts with this many
  // particles uniform over the map's extent (plus 1 m) and drops to pf.particles once they
  // gather on one hypothesis; also the restart after a lost track (kidnapping). 60000:
  // one particle per 0.17 m x 0.17 m of a 60 m x 30 m floor, inside the ~0.1 m wide core of
  // one LED's reprojection likelihood at 2 m (5 px at 460 px focal length) from the
  // nearest particle. The cap: a search keeps as many of them as KLD-sampling asks for the
  // bins they occupy (ParticleFilterOptions::search_kld: ~43 000 around a floor-plan class's
  // copies, all 60 000 uniform over the floor; chosen on floor-plan tuning seeds 1 and 204).
  std::size_t global_particles = 60000;
  // Pixel noise of a decoded LED centre (1 sigma) for the fix covariance.
  double vlc_pixel_sigma = 1.0;
  // Attitude uncertainty (1 sigma, rad) folded into the VLC fix covariance.
  double attitude_sigma_rad = 0.01;
  // Share of dz x attitude_sigma_rad the reported sigma carries (in quadrature with the
  // filter's spread) while the camera anchors the position (FusionEngine::emit: a tilt bias
  // moves every VLC fix alike). The whole of it (1) made the reported sigma too large on
  // most VLC walks: tuning seeds (`--walker random`, consumer IMU), mean share of poses
  // within their 95 % ellipse, seeds 1-10 / 41-50 / 15 s blackouts 41-46: 99.4 / 99.9 /
  // 99.7 % at 1, 98.1 / 99.5 / 99.3 % at 0.7, 94.9 / 98.3 / 98.2 % at 0.5, ATE unchanged.
  // But floor-plan seed 21, whose attitude has a 0.5-0.6 deg tilt bias (the floor was made
  // for it), tracking 3.6-34 s of its kidnap session (tests/app/test_floorplan_e2e.cpp):
  // 94.1 % at 0.7, 82.9 % at 0.5. 0.7: the tilt-biased seed still covered, the others
  // nearer 95 %.
  double tilt_floor_share = 0.7;
  // And the sigma is at least the whole dz x attitude_sigma_rad per axis. Under a high
  // ceiling filmed by a sharp camera several LEDs a frame shrink the spread while all of
  // them share the tilt bias (`sim --world random`, tuning seed 30: 1080p, 3 m above the
  // device, 2.9 LEDs a frame, 4.7 cm error against a 2.5 cm sigma, 89.4 % within the ellipse;
  // with this floor 97 %). The floor alone instead of the quadrature share lost floor-plan
  // seed 21 (94.1 -> 89.0 %): the two together.
  bool tilt_floor_min = true;
  // The camera's frames are weighed at this multiple of their pixel sigma (tight coupling):
  // where the attitude's tilt error dominates a bearing's error and lasts seconds, 30 frames
  // a second are not 30 independent measurements. 1 (frames independent) except for a
  // drone (run_session: 2, with its tilt sigma of 0.05 rad, f x 0.05 = 23 px against 1 px of
  // pixel noise). Chosen on sim drone seeds 1-5 with --camera (tuning), mean ATE camera
  // alone / camera + UWB: x1 0.173 / 0.078 m, x1.5 0.169 / 0.065, x2 0.167 / 0.057, x3
  // 0.174 / 0.055 m; within the 95 % ellipse x1 92 / 98 %, x2 97 / 99.5 %.
  double vlc_frame_correlation = 1.0;
  // Issue 16 part 3: estimate the device height from the camera geometry (two identified
  // LEDs in view, core/vlc/camera_height.hpp) and weigh the frames at it; the pose's z and
  // sigma_z are then estimated. Off: the nominal height (the planar pedestrian case).
  // With a UWB height filter running, the camera's heights go into its z (one height).
  bool camera_height = false;
  VerticalFilterOptions vertical;
  CameraHeightOptions height_camera;
  // Reported sigma_x / sigma_y carry the persistent bias of the absolute fixes' innovations
  // (fixes.csv, UWB fixes, loose VLC fixes; core/fusion/innovation_bias.hpp): the state and
  // the weighing are unchanged. Off with run --no-innovation-bias (for comparisons).
  InnovationBiasOptions innovation_bias;
  // Once per outage the particles' step-length scale and turn slowdown are re-centred on a
  // least-squares fit of the gait to the track the fixes pinned down (pdr, particle filters;
  // core/fusion/gait_regression.hpp). Off with run --no-gait-regression (for comparisons).
  GaitRegressionOptions gait_regression;
  // At the first correction after an outage the particles' yaw offsets are shuffled among
  // them (ParticleFilter::decouple_heading): in the dark each offset turned its particle's
  // track, so the fix would pick the offsets by the cross-track error, whatever made it (the
  // gait in turns, the walking-direction offset), and the yaw jumped by 2-4 deg at the lights'
  // return. Tuning seeds: blackouts 1-10 and 41-50, yaw p95 mean / worst 1.31 / 3.19 -> 1.21 /
  // 2.43 deg (shuffling the walking-direction offsets too: 1.24 / 2.46); heading table 1-10
  // (scripts/heading_table.sh), disturbed field 1.25 -> 1.16 deg, clean 0.99 -> 0.98 deg.
  // Off with run --no-heading-decouple (for comparisons).
  bool decouple_heading_after_outage = true;
  // Sigma of fixes.csv rows that carry none (m).
  double default_fix_sigma_m = 0.2;
  // Poses are written at most at this rate (Hz) on the IMU's timeline; 0 = every IMU sample.
  double output_rate_hz = 50.0;
  // A frame whose observation is older than this when the IMU has moved past is applied
  // late (and counted) rather than waiting for an IMU sample after it.
  double max_frame_hold_s = 0.2;
  // A frame is applied after the IMU sample that follows its exposure (t_obs), up to one IMU
  // period later (10 ms at 100 Hz), and was read with that sample's attitude. A walker turning
  // round on the spot at up to 300 deg/s turned 3 deg in that time: the camera's direct yaw
  // (two LEDs) and the particles' yaw offsets took the error in and moved it into the AHRS
  // (stop 28, `sim --walker random` tuning seed 1: 1.9 and 3.1 deg of yaw error after its two
  // turns, 0.5 and 1.3 deg with the AHRS yaw alone). The attitude is turned back to t_obs by
  // the last body rate when the gap is at most this long (longer: a frame applied late after
  // an IMU dropout, whose rate says nothing of the gap); 0 = never. 0.05 s: five periods of a
  // 100 Hz IMU, two of a 50 Hz one.
  double max_attitude_backdate_s = 0.05;
  // ...and within the frame each LED's row was read at its own time (rolling shutter: a
  // 480-row frame of 30 us rows spans 14 ms, 4 deg of such a turn): each LED's centre is
  // turned to where it would lie at t_obs by the same body rate (VlcFrontend::derotated).
  bool derotate_rows = true;
};

}  // namespace luxloc
