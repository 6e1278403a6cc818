#pragma once
// The fusion stage: IMU attitude (Mahony) and strapdown acceleration drive the planar
// filter's prediction; decoded LED frames and absolute fixes correct it. Camera frames are
// held until the IMU timeline passes their observation time, so each correction is applied
// at the moment its rows were exposed, not when the frame started.
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <set>

#include "core/common/session_config.hpp"
#include "core/fusion/fusion_options.hpp"
#include "core/fusion/fusion_stats.hpp"
#include "core/fusion/motion_source.hpp"
#include "core/fusion/vlc_frontend.hpp"
#include "core/pipeline/fusion_stage.hpp"
#include "core/uwb/uwb_frontend.hpp"
#include "core/vo/vo_options.hpp"

namespace luxloc {

class FusionEngine final : public FusionStage {
 public:
  // `map` and `camera` may be absent (then frames are counted and ignored).
  // UWB anchors come from session.anchors (and from the samples that carry positions).
  FusionEngine(const FusionOptions& options, const std::optional<LedMap>& map,
               const std::optional<CameraModel>& camera, const SessionConfig& session = {},
               const UwbOptions& uwb = {}, const VoOptions& vo = {});
  ~FusionEngine() override;

  void process(const Sample& sample, std::vector<PoseEstimate>& out) override;
  void finish(std::vector<PoseEstimate>& out) override;

  // Called on the fusion thread with every decoded camera frame and its identified LEDs
  // (the live view's camera picture); it must be quick (the live view copies at most a
  // few frames a second and returns).
  using FrameObserver = std::function<void(const FrameSample&, const std::vector<LedObservation>&)>;
  void set_frame_observer(FrameObserver observer) { frame_observer_ = std::move(observer); }
  // Called on the fusion thread after every camera frame with LEDs of reused frequencies
  // that the particle filter weighed in (issue 14): which copy each such blob is at the
  // updated estimate (the association the estimate stands for), and whether the filter was
  // still localising: a global search over the copies, or a spread too wide to name a copy
  // (3 sigma beyond a blob's capture radius). For `run --check-associations`.
  struct AssociationRecord {
    TimeNs t_frame = 0;
    bool localising = false;
    struct Blob {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      int klass = -1;
      int led_index = -1;  // into the map's leds(); -1: no copy of the class near the estimate
    };
    std::vector<Blob> blobs;
  };
  using AssociationObserver = std::function<void(const AssociationRecord&)>;
  void set_association_observer(AssociationObserver observer) { association_observer_ = std::move(observer); }
  // Called from the pose output at most every `interval` (wall clock) with up to `points`
  // particle positions (a strided subsample), for the live view's particle cloud; none
  // for a filter without particles.
  using CloudObserver = std::function<void(const std::vector<Eigen::Vector2d>&)>;
  void set_cloud_observer(CloudObserver observer, std::chrono::milliseconds interval, std::size_t points) {
    cloud_observer_ = std::move(observer);
    cloud_interval_ = interval;
    cloud_points_ = points;
  }
  const FusionStats& stats() const { return stats_; }
  const UwbStats& uwb_stats() const { return uwb_->stats(); }
  const VoStats& vo_stats() const { return vo_stats_; }
  const PlanarFilter& filter() const { return *filter_; }
  const MahonyFilter& attitude() const { return ahrs_; }
  const MotionSource& motion() const { return motion_; }
  double device_height_m() const { return device_height_m_; }

 private:
  void on_imu(const ImuSample& s, std::vector<PoseEstimate>& out);
  void on_frame(const FrameSample& s, std::vector<PoseEstimate>& out);
  void on_fix(const FixSample& s, std::vector<PoseEstimate>& out);
  void on_uwb(const UwbSample& s, std::vector<PoseEstimate>& out);
  void on_vo_frame(const FrameSample& s);
  void apply_frame(const DecodedFrame& f);
  // Frequency reuse (issue 14): particles over the whole map (+1 m).
  // A global search over the map: around every copy of the class of the frame's most
  // telling reused blob (ParticleFilter::initialize_around), else uniform over the map.
  void start_global(TimeNs t, const ReprojectionLikelihood& lik);
  // A search again (lost track, a prior too wide, nothing explained): counted as a restart.
  void restart_global(TimeNs t, const ReprojectionLikelihood& lik);
  // The filter's estimate as an association hint for the single-hypothesis paths.
  std::optional<PoseHint> pose_hint(double yaw_offset_rad);
  void apply_position(const PositionMeasurement& m);
  void predict_to(TimeNs t);
  // The filter's yaw offset of the AHRS now (PF: particle mean; EKF path: the observer).
  struct HeadingState {
    double offset_rad = 0.0;
    double sigma_rad = std::numeric_limits<double>::quiet_NaN();
  };
  HeadingState heading_state();
  // Moves the offset `h` (heading_state() now: the caller has it already, one pass over
  // the particles less) into the AHRS when it is well determined (HeadingFeedback), at t.
  void feed_back_heading(TimeNs t, const HeadingState& h);
  // Seconds since the heading was last fixed (drift clock of the yaw offset).
  double heading_drift_s(TimeNs t) const;
  // The AHRS's magnetometer corrects its yaw (within the last second): its error is bounded.
  bool heading_bounded() const;
  // R_BtoW with the fused yaw: Rz(offset) R_ahrs, the AHRS's at t (ahrs_R_BtoW_at).
  Eigen::Matrix3d fused_R_BtoW(TimeNs t);
  // The AHRS's attitude turned back from the last IMU sample to t by the last body rate
  // (FusionOptions::max_attitude_backdate_s); the attitude now when t is not just before it.
  Eigen::Matrix3d ahrs_R_BtoW_at(TimeNs t) const;
  // False for an absolute sample (frame, fix) that options_.absolute_for_s excludes.
  bool absolute_wanted(TimeNs t);
  void emit(TimeNs t, std::vector<PoseEstimate>& out, bool force);

  FusionOptions options_;
  std::optional<StartPose> start_;  // options_.start, else the session's; used once
  FusionStats stats_;
  MahonyFilter ahrs_;
  HeadingFeedback heading_feedback_;
  // The EKF path's (and a filter without the heading state's) yaw offset.
  std::optional<HeadingObserver> heading_observer_;
  std::unique_ptr<PlanarFilter> filter_;
  ParticleFilter* pf_ = nullptr;  // filter_ when it is a particle filter (tight coupling)
  double ceiling_distance_m_ = 2.0;
  double mean_led_z_m_ = 3.0;  // the map's mean LED height
  double focal_px_ = 500.0;
  int consecutive_gated_ = 0;
  int consecutive_unexplained_ = 0;
  std::set<int> search_leds_;  // distinct LED classes weighed since the global search began  // frames no particle of a global search explains
  std::optional<TimeNs> t_global_start_;  // the running global localisation began
  double vlc_ceiling_distance() const { return ceiling_distance_m_; }
  double vlc_focal_px() const { return focal_px_; }
  std::unique_ptr<VlcFrontend> vlc_;
  double device_height_m_;
  // Issue 16 part 3: the height from the camera (FusionOptions::camera_height) when no UWB
  // height filter carries z. Fed by camera_height_from(); read by height_now().
  std::optional<VerticalFilter> vertical_;
  // Without it, the same filter as a check of the nominal height (read at the end only).
  std::optional<VerticalFilter> height_check_;
  void camera_height_from(const DecodedFrame& f, const Eigen::Matrix3d& R_BtoW);
  // The device height now (learnt by the camera or the ranges, else nominal) and its sigma
  // (NaN: nominal, not estimated).
  std::pair<double, double> height_now() const;
  std::deque<DecodedFrame> pending_frames_;
  TimeNs t_filter_ = 0;      // time the filter state refers to
  bool have_imu_ = false;
  TimeNs t_imu_ = 0;
  MotionSource motion_;  // the prediction's input (pdr / strapdown / cv)
  TimeNs t_last_emit_ = 0;
  bool emitted_ = false;
  int last_leds_ = 0;
  TimeNs t_last_fix_ = 0;
  TimeNs gait_widened_at_fix_ = -1;  // t_last_fix_ of the outage whose gait spread was widened
  // Whether the filter restarted (stats_.reinitializations moved) since `seen` last caught
  // up with it; catches it up. Each consumer of restarts keeps its own `seen`.
  bool restarted_since(std::uint64_t& seen) {
    const bool moved = seen != stats_.reinitializations;
    seen = stats_.reinitializations;
    return moved;
  }
  // The gait fitted to the tracked stretches (FusionOptions::gait_regression); cleared after
  // any restart (stats_.reinitializations moved since gait_regression_reinits_).
  GaitRegression gait_regression_;
  std::uint64_t gait_regression_reinits_ = 0;
  void feed_gait_regression(TimeNs t, const MotionInput& u);
  TimeNs heading_decoupled_at_fix_ = -1;  // t_last_fix_ of the outage whose offsets were shuffled
  void before_correction();
  std::optional<TimeNs> t_last_vlc_;  // the last camera frame that corrected the position
  std::optional<TimeNs> t_initialized_;
  std::uint64_t reinits_seen_ = 0;      // stats_.reinitializations at the last pose
  std::optional<TimeNs> t_last_reinit_;  // time of the first pose after the last restart  // sample time at which the filter first initialised
  std::unique_ptr<UwbFrontend> uwb_;
  int uwb_disagreements_ = 0;
  // The fixes' innovations before they weighed (FusionOptions::innovation_bias): their
  // persistent mean widens the reported sigma. Read through innovation_bias(), which clears
  // it after any restart (stats_.reinitializations moved since innovation_reinits_).
  InnovationBias innovation_bias_;
  std::uint64_t innovation_reinits_ = 0;
  InnovationBias& innovation_bias();
  void note_innovation(TimeNs t, const PositionMeasurement& m, const PlanarEstimate& before);
  bool walker_ = false;  // a gait was confirmed (pdr): the yaw offset reverts by walker_bounded_rad
  // The latest UWB fixes before the filter started (UwbOptions::start_agreeing_fixes).
  std::deque<PositionMeasurement> uwb_start_fixes_;
  // The fix to start at once start_agreeing_fixes agree: their information-weighted mean
  // with the newest fix's covariance (not shrunk: the fixes share the anchors' biases).
  std::optional<PositionMeasurement> uwb_start_agreed(const PositionMeasurement& fix);
  VoOptions vo_options_;
  std::unique_ptr<FloorOdometry> vo_;  // --vo with a camera
  VoStats vo_stats_;
  double vo_heading_ = 0.0;
  bool vo_heading_valid_ = false;
  FrameObserver frame_observer_;
  AssociationObserver association_observer_;
  CloudObserver cloud_observer_;
  std::chrono::milliseconds cloud_interval_{333};
  std::size_t cloud_points_ = 0;
  std::chrono::steady_clock::time_point last_cloud_{};
};

}  // namespace luxloc
