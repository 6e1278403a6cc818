#include "core/fusion/fusion_engine.hpp"

#include <Eigen/Eigenvalues>

#include "core/filter/filter_factory.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {
namespace {

// Consecutive corrections refused before a pose says "lost": 3 frames (0.1 s at 30 fps)
// of disagreement are no longer noise; the restart follows at max_consecutive_rejections.
constexpr int kLostAfterGated = 3;

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
// Explicit guide: clang 14 (the sanitizer builds) has no aggregate CTAD yet.
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

MotionSourceOptions effective_motion(const FusionOptions& o) {
  MotionSourceOptions m = o.motion;
  if (!o.use_imu || !o.use_accelerometer) m.model = MotionModel::cv;
  m.gravity = m.pdr.gravity = o.ahrs.gravity;
  // The particle filter carries the walker's whole turn slowdown per particle (GaitNoise::
  // turn_slowdown_*, in m/rad); the gait model's fixed factor stays for the EKF.
  if (o.filter != "ekf") m.gait.turn_slowdown_s_per_rad = 0.0;
  return m;
}

// The gait regression's options, its window-rejection prior the particles' own start.
GaitRegressionOptions gait_regression_options(const FusionOptions& o) {
  GaitRegressionOptions r = o.gait_regression;
  r.reject_prior_scale = o.pf.gait.scale0;
  r.reject_prior_turn_slowdown = o.pf.gait.turn_slowdown0;
  return r;
}

// One set of process-noise knobs for both filter families.
EkfOptions ekf_options(const ParticleFilterOptions& pf) {
  EkfOptions e;
  e.accel_noise_psd = pf.accel_noise_psd;
  e.velocity_tau_s = pf.velocity_tau_s;
  e.max_speed = pf.max_speed;
  e.init_speed_sigma = pf.init_speed_sigma;
  e.max_consecutive_rejections = pf.max_consecutive_rejections;
  e.gait = pf.gait;
  return e;
}

}  // namespace

FusionEngine::FusionEngine(const FusionOptions& options, const std::optional<LedMap>& map,
                           const std::optional<CameraModel>& camera, const SessionConfig& session,
                           const UwbOptions& uwb, const VoOptions& vo)
    : options_(options),
      ahrs_(options.ahrs),
      heading_feedback_(options.heading_feedback),
      motion_(effective_motion(options)),
      gait_regression_(gait_regression_options(options)),
      innovation_bias_(options.innovation_bias),
      vo_options_(vo) {
  device_height_m_ = std::isfinite(options.device_height_m) ? options.device_height_m
                     : std::isfinite(session.device_height_m) ? session.device_height_m
                                                              : 1.0;
  // Heading state (issue 11): per particle when the particle filter weighs the camera
  // itself (tight coupling); otherwise (EKF, loose coupling) the scalar HeadingObserver
  // corrected by the camera's direct yaw. pf.heading.enabled = false: neither (the AHRS
  // yaw unchanged, as before).
  start_ = options.start ? options.start : session.start;
  if (start_ && std::isfinite(options.start_sigma_m) && options.start_sigma_m > 0.0) start_->sigma_m = options.start_sigma_m;
  ParticleFilterOptions pf_options = options.pf;
  pf_options.heading.enabled = options.pf.heading.enabled && options.tight_coupling;
  filter_ = make_planar_filter(FilterSettings{options.filter, pf_options, ekf_options(options.pf)});
  pf_ = dynamic_cast<ParticleFilter*>(filter_.get());
  if (options.pf.heading.enabled && !(pf_ && pf_->options().heading.enabled)) heading_observer_.emplace(options.pf.heading);
  uwb_ = std::make_unique<UwbFrontend>(uwb, UwbAnchorTable(session.anchors), device_height_m_);
  if (vo.enabled && camera)
    vo_ = std::make_unique<FloorOdometry>(*camera, device_height_m_ + camera->p_CinB.z(), vo.odometry);
  if (map && camera && !map->empty()) {
    vlc_ = std::make_unique<VlcFrontend>(*camera, *map, options_, device_height_m_);
    double z = 0.0;
    for (const Led& l : map->leds()) z += l.p_inW.z();
    mean_led_z_m_ = z / static_cast<double>(map->size());
    ceiling_distance_m_ = std::max(0.5, mean_led_z_m_ - device_height_m_);
    focal_px_ = 0.5 * (camera->fx + camera->fy);
    if (options.camera_height)
      vertical_.emplace(options.vertical, device_height_m_);
    else
      height_check_.emplace(options.vertical, device_height_m_);
  }
}

void FusionEngine::camera_height_from(const DecodedFrame& f, const Eigen::Matrix3d& R_BtoW) {
  if (!vlc_) return;
  if (height_check_ && !uwb_->estimates_height()) {
    // The nominal height is used, but is it right? The camera's heights go into a filter of
    // their own that nothing reads until the summary (FusionStats::height_check_*).
    CameraHeightOptions o = options_.height_camera;
    o.pixel_sigma = options_.vlc_pixel_sigma;
    o.attitude_sigma_rad = options_.attitude_sigma_rad;
    for (CameraHeight h : vlc_->heights(f, R_BtoW, height_check_->height_m(), o)) {
      h.sigma_m *= o.frame_correlation;
      if (height_check_->update(f.t_obs, h.z_m, h.sigma_m) == VerticalFilter::Outcome::used) ++stats_.height_check_used;
    }
  }
  if (!(options_.camera_height || uwb_->estimates_height())) return;  // the nominal height
  if (options_.camera_height) {
    const bool in_uwb = uwb_->estimates_height() && uwb_->height_bias().started();
    CameraHeightOptions o = options_.height_camera;
    o.pixel_sigma = options_.vlc_pixel_sigma;
    o.attitude_sigma_rad = options_.attitude_sigma_rad;  // the platform's (run --attitude-sigma)
    const std::vector<CameraHeight> hs = vlc_->heights(f, R_BtoW, height_now().first, o);
    for (CameraHeight h : hs) {
      h.sigma_m *= o.frame_correlation;  // CameraHeightOptions::frame_correlation
      bool used = false;
      if (in_uwb) {
        used = uwb_->observe_height(f.t_obs, h.z_m, h.sigma_m) == HeightBiasFilter::Outcome::used;
      } else if (vertical_) {
        const std::uint64_t reopened = vertical_->stats().reopened;
        used = vertical_->update(f.t_obs, h.z_m, h.sigma_m) == VerticalFilter::Outcome::used;
        stats_.camera_height_reopened += vertical_->stats().reopened - reopened;
      }
      ++(used ? stats_.camera_heights_used : stats_.camera_heights_gated);
      stats_.camera_height_in_uwb = in_uwb;
    }
    if (hs.empty() && vertical_ && !in_uwb) vertical_->predict(f.t_obs);
  }
  // The frame is weighed at the learnt height (the camera's or the ranges'); the gate and
  // the pose's sigma floor scale with the distance to the ceiling.
  const double z = height_now().first;
  vlc_->set_device_height_m(z);
  ceiling_distance_m_ = std::max(0.5, mean_led_z_m_ - z);
}

std::pair<double, double> FusionEngine::height_now() const {
  // The UWB height filter once it runs (the camera's heights go into it then), else the
  // camera's own, else the nominal height.
  if (uwb_->estimates_height() && (uwb_->height_bias().started() || !vertical_))
    return {uwb_->height_m(), uwb_->height_sigma_m()};
  if (vertical_) return {vertical_->height_m(), vertical_->height_sigma_m()};
  return {device_height_m_, std::numeric_limits<double>::quiet_NaN()};
}

FusionEngine::~FusionEngine() = default;

void FusionEngine::process(const Sample& sample, std::vector<PoseEstimate>& out) {
  std::visit(Overloaded{
                 [&](const ImuSample& s) { on_imu(s, out); },
                 [&](const FrameSample& s) {
                   if (vo_) on_vo_frame(s);
                   if (options_.use_vlc && absolute_wanted(s.t)) on_frame(s, out);
                 },
                 [&](const FixSample& s) {
                   if (options_.use_fixes && absolute_wanted(s.t)) on_fix(s, out);
                 },
                 [&](const UwbSample& s) {
                   if (!uwb_->options().enabled)
                     ++stats_.other_samples;
                   else if (absolute_wanted(s.t))
                     on_uwb(s, out);
                 },
                 [&](const auto&) { ++stats_.other_samples; },
             },
             sample.data);
  if (!t_initialized_ && filter_->initialized()) t_initialized_ = sample.t;
  // Frames cannot wait for an IMU sample forever (IMU dropout): apply them late.
  const TimeNs hold = seconds_to_ns(options_.max_frame_hold_s);
  while (!pending_frames_.empty() && sample.t - pending_frames_.front().t_obs > hold) {
    apply_frame(pending_frames_.front());
    pending_frames_.pop_front();
  }
}

void FusionEngine::finish(std::vector<PoseEstimate>& out) {
  while (!pending_frames_.empty()) {
    apply_frame(pending_frames_.front());
    pending_frames_.pop_front();
  }
  // The last IMU time, unless that pose is out already (no two poses share a time).
  if (filter_->initialized() && have_imu_ && (!emitted_ || t_imu_ > t_last_emit_)) emit(t_imu_, out, true);
  // Without a single IMU sample every prediction was constant velocity, whatever --motion.
  stats_.motion = have_imu_ ? to_string(motion_.model()) : "cv (no IMU samples)";
  stats_.steps = motion_.steps();
  stats_.motion_auto = motion_.model() == MotionModel::pdr && options_.motion.gait_gate;
  stats_.steps_used = motion_.steps_used();
  stats_.impact_samples = motion_.impact_samples();
  stats_.regime_s = motion_.regime_seconds();
  stats_.turning_in_place_s = motion_.turning_in_place_s();
  if (const auto& l = motion_.lever_arm().lever()) {
    stats_.lever_forward_m = l->x();
    stats_.lever_left_m = l->y();
  }
  stats_.lever_turns = motion_.lever_arm().turns_used();
  uwb_->summarize_online();
  if (pf_) {
    if (const ParticleFilter::GaitEstimate g = pf_->gait_estimate(); g.valid) {
      stats_.gait_scale = g.scale;
      stats_.gait_heading_offset_rad = g.heading_offset_rad;
    }
  } else if (const auto* ekf = dynamic_cast<const EkfFilter*>(filter_.get()); ekf && motion_.model() == MotionModel::pdr) {
    stats_.gait_scale = ekf->full_state()(4);
    stats_.gait_heading_offset_rad = ekf->full_state()(5);
  }
  stats_.heading_transfers = heading_feedback_.transfers();
  stats_.heading_learnt_rate_rps = heading_feedback_.learnt_rate_rps();
  if (options_.camera_height && vlc_) std::tie(stats_.final_height_m, stats_.final_height_sigma_m) = height_now();
  if (height_check_ && stats_.height_check_used > 0) {
    stats_.height_check_m = height_check_->height_m();
    stats_.height_check_sigma_m = height_check_->height_sigma_m();
    stats_.nominal_height_m = device_height_m_;
  }
  if (filter_->initialized()) stats_.sigma_yaw_rad = heading_state().sigma_rad;
}

FusionEngine::HeadingState FusionEngine::heading_state() {
  HeadingState h;
  if (pf_ && pf_->has_heading()) {
    if (const ParticleFilter::HeadingEstimate e = pf_->heading_estimate(); e.valid) {
      h.offset_rad = e.offset_rad;
      h.sigma_rad = e.sigma_rad;
    }
  } else if (heading_observer_) {
    h.offset_rad = heading_observer_->offset_rad();
    h.sigma_rad = heading_observer_->sigma_rad();
  }
  return h;
}

void FusionEngine::feed_back_heading(TimeNs t, const HeadingState& h) {
  const std::optional<HeadingFeedback::Transfer> tr = heading_feedback_.update(t, h.offset_rad, h.sigma_rad);
  if (!tr) return;
  ahrs_.correct_heading(tr->dyaw_rad, tr->drate_rps);
  if (pf_ && pf_->has_heading())
    pf_->shift_heading(tr->dyaw_rad);
  else if (heading_observer_)
    heading_observer_->shift(tr->dyaw_rad);
}

double FusionEngine::heading_drift_s(TimeNs t) const {
  // Before the first transfer the clock runs from the filter's start: the yaw-offset prior
  // (HeadingNoise::sigma0_rad) is what is known of the heading then.
  double s = heading_feedback_.since_fix_s(t);
  if (!std::isfinite(s) && t_initialized_) s = std::max(0.0, ns_to_seconds(t - *t_initialized_));
  // A magnetometer in use bounds the AHRS's yaw error (FusionOptions::mag_bounded_drift_s).
  if (heading_bounded()) s = std::min(s, options_.mag_bounded_drift_s);
  return s;
}

bool FusionEngine::heading_bounded() const { return ahrs_.since_mag_correction_s() < 1.0; }

Eigen::Matrix3d FusionEngine::fused_R_BtoW(TimeNs t) {
  const HeadingState h = heading_state();
  return Eigen::AngleAxisd(h.offset_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() * ahrs_R_BtoW_at(t);
}

// R(t_imu - dt) = R(t_imu) Exp(-omega_B dt) for a body rate omega_B held over the gap.
Eigen::Matrix3d FusionEngine::ahrs_R_BtoW_at(TimeNs t) const {
  const double back = ns_to_seconds(t_imu_ - t);
  const Eigen::Vector3d w = ahrs_.gyro_corrected();
  if (!have_imu_ || !(back > 0.0) || back > options_.max_attitude_backdate_s || !w.allFinite() || w.norm() == 0.0)
    return ahrs_.R_BtoW();
  return ahrs_.R_BtoW() * Eigen::AngleAxisd(-w.norm() * back, w.normalized()).toRotationMatrix();
}

bool FusionEngine::absolute_wanted(TimeNs t) {
  if (!t_initialized_ || !std::isfinite(options_.absolute_for_s) ||
      ns_to_seconds(t - *t_initialized_) <= options_.absolute_for_s)
    return true;
  ++stats_.corrections_ignored;
  return false;
}

void FusionEngine::predict_to(TimeNs t) {
  if (!filter_->initialized()) {
    t_filter_ = t;
    return;
  }
  if (t <= t_filter_) return;
  MotionInput u = motion_.input(t_filter_, t);
  u.heading_drift_s = heading_drift_s(t_filter_);
  // Mean reversion of the yaw offset while the magnetometer bounds the AHRS's yaw: for a
  // platform that does not walk HeadingNoise::bounded_rad, for a walker walker_bounded_rad
  // (its track's heading goes to the walking-direction offset d; e only holds the AHRS's
  // error). Per platform, not per moment: a walker stays one while it stands.
  if (motion_.model() == MotionModel::pdr && motion_.gait_confirmed()) walker_ = true;
  {
    const HeadingNoise& n = options_.pf.heading;
    u.heading_bound_rad = !heading_bounded() ? 0.0 : walker_ ? n.walker_bounded_rad : n.bounded_rad;
    // A walker in the dark after the camera measured e: for the next HeadingNoise::
    // max_drift_s (the drift clock's own horizon, 60 s) the camera's e is the better
    // reference and is kept, not pulled towards an AHRS that may be off in a bent field.
    // Tuning seeds: the heading table's 1 deg/s bias + disturbed field + 15 s blackout
    // (scripts/heading_table.sh 1 10) max error 0.471 -> 0.416 m, yaw p95 1.97 -> 1.52 deg;
    // the clean blackouts of seeds 41-50 mean maximum 0.369 -> 0.354 m.
    if (walker_ && t_last_vlc_) {
      const double dark_s = ns_to_seconds(t_filter_ - *t_last_vlc_);
      if (dark_s > 1.0 && dark_s < n.max_drift_s) u.heading_bound_rad = 0.0;
    }
  }
  // Dead reckoning: once per outage the gait calibration's spread grows to the model's
  // real error from one stretch to the next (GaitNoise::dead_reckoning_*).
  if (pf_ && u.has_gait && gait_widened_at_fix_ != t_last_fix_ &&
      ns_to_seconds(t - t_last_fix_) >= options_.pf.gait.dead_reckoning_after_s) {
    // First the calibration the tracked stretches fit (core/fusion/gait_regression.hpp), then
    // its spread. Shifting every particle keeps each one's deviation and the set's spread.
    if (const ParticleFilter::GaitEstimate g = pf_->gait_estimate(); g.valid) {
      if (const auto fit = gait_regression_.solve(g.scale, g.turn_slowdown_m_per_rad)) {
        pf_->shift_gait(fit->scale - g.scale, fit->turn_slowdown_m_per_rad - g.turn_slowdown_m_per_rad);
        ++stats_.gait_recentred;
        stats_.max_gait_recentre_scale = std::max(stats_.max_gait_recentre_scale, std::abs(fit->scale - g.scale));
      }
    }
    pf_->widen_gait(options_.pf.gait.dead_reckoning_scale_sigma, options_.pf.gait.dead_reckoning_heading_offset_sigma);
    gait_widened_at_fix_ = t_last_fix_;
  }
  filter_->predict(u);
  if (heading_observer_) heading_observer_->predict(u.dt, u.heading_drift_s, u.heading_bound_rad);
  if (pf_ && u.has_gait && options_.gait_regression.enabled) feed_gait_regression(t, u);
  t_filter_ = t;
}

// The first correction after an outage (one the gait spread was widened for): the
// particles' yaw offsets are shuffled first (FusionOptions::decouple_heading_after_outage).
void FusionEngine::before_correction() {
  if (!options_.decouple_heading_after_outage || !pf_ || gait_widened_at_fix_ != t_last_fix_ ||
      heading_decoupled_at_fix_ == t_last_fix_)
    return;
  heading_decoupled_at_fix_ = t_last_fix_;
  pf_->decouple_heading(false);
  ++stats_.headings_decoupled;
}

void FusionEngine::feed_gait_regression(TimeNs t, const MotionInput& u) {
  if (restarted_since(gait_regression_reinits_)) gait_regression_.reset();  // windows would span the jump
  const PlanarEstimate est = pf_->estimate();
  if (!est.valid) return;
  // The walking direction the particles used (AHRS heading + yaw offset + gait offset): their
  // mean velocity's. Standing (no velocity), the gait speed is zero and adds nothing.
  const double vn = est.v.norm();
  if (vn > 0.05) gait_regression_.add_motion(u.gait.speed_mps, u.gait.turn_paid_rps, est.v / vn, u.dt);
  const double max_var = est.cov_p.allFinite()
                             ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(est.cov_p, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff()
                             : std::numeric_limits<double>::infinity();
  const GaitRegressionOptions& o = options_.gait_regression;
  const bool tracking = ns_to_seconds(t - t_last_fix_) < o.fix_age_s && max_var < o.tracking_sigma_m * o.tracking_sigma_m;
  gait_regression_.add_position(t, est.p, tracking);
}

void FusionEngine::on_imu(const ImuSample& raw, std::vector<PoseEstimate>& out) {
  ++stats_.imu_samples;
  if (!raw.acc_inB.allFinite() || !raw.gyro_inB.allFinite() || (have_imu_ && raw.t <= t_imu_)) {
    ++stats_.imu_rejected;
    return;
  }
  const ImuSample s = options_.imu_calibration.apply(raw);
  const bool first = !have_imu_;
  // The accelerometer is a gravity reference only without motion: remove the centripetal
  // acceleration omega x v (body frame) that turns add, using the filter's velocity, so a
  // walker's turns do not tilt the attitude (and with it every VLC bearing).
  ImuSample compensated = s;
  if (options_.compensate_centripetal && ahrs_.initialized() && filter_->initialized()) {
    const PlanarEstimate e = filter_->estimate();
    if (e.valid) {
      const Eigen::Vector3d v_inB = ahrs_.R_BtoW().transpose() * Eigen::Vector3d(e.v.x(), e.v.y(), 0.0);
      compensated.acc_inB -= (s.gyro_inB - ahrs_.gyro_bias()).cross(v_inB);
    }
  }
  ahrs_.hold_magnetometer(heading_feedback_.since_fix_s(s.t) < heading_feedback_.options().mag_hold_s);
  ahrs_.update(compensated);
  if (start_ && !filter_->initialized() && ahrs_.initialized()) {
    // Dead reckoning from a known pose (issue 12): the yaw, when given, replaces the AHRS's.
    if (std::isfinite(start_->yaw))
      ahrs_.correct_heading(std::remainder(start_->yaw - ahrs_.yaw(), 2.0 * 3.14159265358979323846), 0.0);
    filter_->initialize(start_->p_inW, Eigen::Matrix2d::Identity() * start_->sigma_m * start_->sigma_m);
    t_filter_ = s.t;
    ++stats_.started_at_known_pose;
    start_.reset();
  }
  if (ahrs_.initialized()) motion_.update(s, ahrs_.R_BtoW());
  have_imu_ = true;
  t_imu_ = s.t;
  if (first && !filter_->initialized()) t_filter_ = s.t;
  // Corrections from frames exposed before this sample, each at its own time.
  while (!pending_frames_.empty() && pending_frames_.front().t_obs <= s.t) {
    predict_to(pending_frames_.front().t_obs);
    apply_frame(pending_frames_.front());
    pending_frames_.pop_front();
  }
  predict_to(s.t);
  emit(s.t, out, false);
}

void FusionEngine::on_frame(const FrameSample& s, std::vector<PoseEstimate>&) {
  ++stats_.frames;
  if (!vlc_) return;
  DecodedFrame f = vlc_->decode(s);
  if (frame_observer_) frame_observer_(s, accepted_leds(f));
  stats_.blobs_rejected += static_cast<std::uint64_t>(f.rejected);
  last_leds_ = f.leds;
  if (f.leds == 0) return;
  ++stats_.frames_with_leds;
  stats_.leds_decoded += static_cast<std::uint64_t>(f.leds);
  pending_frames_.push_back(std::move(f));
}

void FusionEngine::apply_frame(const DecodedFrame& decoded) {
  if (!ahrs_.initialized()) {
    ++stats_.frames_without_attitude;
    return;
  }
  // The rows as a global shutter at t_obs saw them, by the body rate of the IMU sample just
  // after (FusionOptions::derotate_rows; not for a frame applied late after a dropout).
  const double age_s = ns_to_seconds(t_imu_ - decoded.t_obs);
  const DecodedFrame f = options_.derotate_rows && age_s >= 0.0 && age_s <= options_.max_attitude_backdate_s
                             ? vlc_->derotated(decoded, ahrs_.gyro_corrected())
                             : decoded;
  const Eigen::Matrix3d R_BtoW = ahrs_R_BtoW_at(f.t_obs);
  camera_height_from(f, R_BtoW);  // issue 16 part 3: the frame is weighed at the height it measured
  // Frequency reuse without a start: no LED of a frequency of its own in view, so no
  // loose fix can start the filter; the particles start everywhere (global localisation).
  if (pf_ && !pf_->initialized() && options_.tight_coupling && vlc_->reuses_frequencies()) {
    if (!vlc_->fix(f, fused_R_BtoW(f.t_obs))) {
      start_global(f.t_obs, vlc_->likelihood(f, R_BtoW));
      ++stats_.global_starts;
    }
  }
  if (pf_ && pf_->initialized() && options_.tight_coupling) {
    // Tight coupling: weigh every particle by the reprojection error of every LED (each
    // particle picks the copies of reused frequencies its own pose points at).
    const ReprojectionLikelihood lik = vlc_->likelihood(f, R_BtoW);
    if (lik.size() == 0) return;
    // A prior too wide to name the copies (3 sigma beyond a reused blob's capture radius:
    // two copies of its class inside the cloud, after a long time in the dark) is no prior:
    // one frame would collapse the cloud onto whichever copy its particles reach first. A
    // global search instead, which holds every copy until the walk tells them apart.
    if (!pf_->localising() && lik.has_reused()) {
      const std::optional<PoseHint> prior = pose_hint(heading_state().offset_rad);
      for (std::size_t i = 0; i < lik.size() && prior; ++i) {
        const int k = lik.term(i).klass;
        if (k < 0 || 3.0 * prior->sigma_m < vlc_->capture_radius(k)) continue;
        restart_global(f.t_obs, lik);
        break;
      }
    }
    ++stats_.vlc_fixes;
    for (std::size_t i = 0; i < lik.size(); ++i) stats_.reused_blobs += lik.term(i).klass >= 0 ? 1 : 0;
    // Gate: the mean particle's reprojection error, in metres at the ceiling distance,
    // against the filter's spread. Persistent disagreement means the filter lost track.
    // The yaw offset's spread moves the LEDs too: by sigma_yaw times their distance.
    const PlanarEstimate e = pf_->estimate();
    const HeadingState h = heading_state();
    const double rms_m = lik.rms_px(e.p.x(), e.p.y(), h.offset_rad) * vlc_ceiling_distance() / vlc_focal_px();
    const double yaw_spread = std::isfinite(h.sigma_rad) ? h.sigma_rad * vlc_ceiling_distance() : 0.0;
    const double allowed = options_.tight_gate_m + 3.0 * std::sqrt(e.cov_p.trace() + yaw_spread * yaw_spread);
    // While the particles still search the whole map (several copies held at once) their
    // mean stands between hypotheses: no gate then, every particle weighs its own copy.
    // Tempered too (likelihood^(1/9), the pixel sigma x 3): two copies' hypotheses that
    // both explain the blobs within a few pixels (the heading is free while searching) stay
    // until a new LED tells them apart, instead of one winning on noise in a few frames.
    const bool searching = pf_->localising();
    // A search is not gated, but it can have lost every copy (the true one thinned out, or
    // a kidnap during it): then no particle explains the frame (each blob beyond the
    // outlier distance at a stride of 256 particles) and the tempered weights are flat.
    // As many such frames in a row as a tracking filter may gate: the search starts again.
    if (searching) {
      bool explained = false;
      const std::size_t n = pf_->size(), stride = std::max<std::size_t>(1, n / 256);
      for (std::size_t i = 0; i < n && !explained; i += stride) {
        const Eigen::Vector2d p = pf_->position(i);
        explained = lik.rms_px(p.x(), p.y(), pf_->yaw_offset(i)) < lik.outlier_px();
      }
      if (explained) {
        consecutive_unexplained_ = 0;
      } else if (++consecutive_unexplained_ >= options_.pf.max_consecutive_rejections) {
        consecutive_unexplained_ = 0;
        restart_global(f.t_obs, lik);
      }
    }
    if (!searching && rms_m <= allowed) before_correction();
    if ((searching || rms_m <= allowed) && pf_->weigh(searching ? lik.tempered(1.0 / 9.0) : lik) &&
        pf_->normalize_and_resample()) {
      ++stats_.fixes_accepted;
      consecutive_gated_ = 0;
      t_last_fix_ = f.t_obs;
      t_last_vlc_ = f.t_obs;
      // A search converges only after four distinct LEDs: each LED where a hypothesis puts
      // one of its class leaves about 1/12 of the wrong copies (12 classes), so of a
      // class's ~37 copies 37 / 12^3 = 0.02 wrong ones are expected to last past four; a
      // tight cloud after fewer is one copy that won the noise (seen on seeds 101 and 204:
      // wrong copies for 1-2 s until the gate caught them). An LED of a frequency of its
      // own names its place and counts as all four.
      if (searching) {
        for (std::size_t i = 0; i < lik.size(); ++i) {
          const int k = lik.term(i).klass;
          if (k >= 0)
            search_leds_.insert(k);
          else
            search_leds_.insert({-1, -2, -3, -4});
        }
        if (search_leds_.size() >= 4) pf_->hold_search(false);
      }
      if (association_observer_ && lik.has_reused()) {
        const PlanarEstimate now = pf_->estimate();
        const double offset = heading_state().offset_rad;
        AssociationRecord r;
        r.t_frame = f.t_frame;
        r.localising = pf_->localising();
        const std::optional<PoseHint> hint = pose_hint(offset);
        for (std::size_t i = 0; i < lik.size(); ++i) {
          const int k = lik.term(i).klass;
          if (k < 0) continue;
          r.localising = r.localising || !hint || 3.0 * hint->sigma_m >= vlc_->capture_radius(k);
          r.blobs.push_back({lik.term(i).uv, k, lik.associate(i, now.p.x(), now.p.y(), offset)});
        }
        association_observer_(r);
      }
      if (t_global_start_ && !pf_->localising()) {  // the global set has gathered on one copy
        const double after = ns_to_seconds(f.t_obs - *t_global_start_);
        if (!std::isfinite(stats_.global_converged_s)) stats_.global_converged_s = after;
        if (!stats_.global_searches.empty()) stats_.global_searches.back().converged_after_s = after;
        t_global_start_.reset();
      }
      // Only a frame that sees the heading directly (two or more LEDs) may move it into
      // the AHRS, and only when the particles' offset agrees with that frame's own yaw
      // (VlcFrontend::yaw_offset, 3 sigma): one LED ties yaw to position, and a cloud that
      // collapsed onto a wrong yaw-position pair would teach the AHRS a wrong yaw and bias.
      if (lik.size() >= 2 && !pf_->localising()) {
        if (const std::optional<YawMeasurement> y = vlc_->yaw_offset(f, R_BtoW, pose_hint(heading_state().offset_rad))) {
          const HeadingState now = heading_state();
          const double d = std::remainder(now.offset_rad - y->offset_rad, 2.0 * 3.14159265358979323846);
          if (std::abs(d) <= 3.0 * std::hypot(y->sigma_rad, std::isfinite(now.sigma_rad) ? now.sigma_rad : 0.0)) {
            ++stats_.camera_yaw_used;
            feed_back_heading(f.t_obs, now);
          } else {
            ++stats_.camera_yaw_rejected;
          }
        }
      }
      return;
    }
    ++stats_.fixes_gated;
    if (++consecutive_gated_ < options_.pf.max_consecutive_rejections) return;
    // Lost: fall through to a loose fix, which re-initialises the filter; in a reuse map
    // with no LED of its own frequency in view, the restart is global (kidnapping).
    consecutive_gated_ = 0;
    if (vlc_->reuses_frequencies() && !vlc_->fix(f, fused_R_BtoW(f.t_obs))) {
      restart_global(f.t_obs, lik);
      return;
    }
    if (std::optional<PositionMeasurement> m = vlc_->fix(f, fused_R_BtoW(f.t_obs))) {
      pf_->initialize(m->z, m->R * 4.0);
      ++stats_.reinitializations;
      t_last_fix_ = f.t_obs;
    }
    return;
  }
  // EKF / loose coupling: the camera's direct yaw (two or more LEDs) corrects the heading
  // observer, then the fix is made with the fused yaw.
  if (heading_observer_) {
    if (const std::optional<YawMeasurement> y = vlc_->yaw_offset(f, R_BtoW, pose_hint(heading_state().offset_rad))) {
      if (heading_observer_->correct(*y)) {
        ++stats_.camera_yaw_used;
        feed_back_heading(f.t_obs, heading_state());
      } else {
        ++stats_.camera_yaw_rejected;
      }
    }
  }
  std::optional<PositionMeasurement> m = vlc_->fix(f, fused_R_BtoW(f.t_obs), pose_hint(0.0));
  if (!m) return;
  ++stats_.vlc_fixes;
  apply_position(*m);
  t_last_vlc_ = f.t_obs;
}

void FusionEngine::restart_global(TimeNs t, const ReprojectionLikelihood& lik) {
  start_global(t, lik);
  ++stats_.global_restarts;
  ++stats_.reinitializations;
}

void FusionEngine::start_global(TimeNs t, const ReprojectionLikelihood& lik) {
  if (!filter_->initialized()) t_filter_ = have_imu_ ? t_imu_ : t;
  t_global_start_ = t;
  search_leds_.clear();
  pf_->hold_search(true);
  stats_.global_searches.push_back({ns_to_seconds(t), std::numeric_limits<double>::quiet_NaN()});
  // The blob whose class has the fewest copies: the fewest hypotheses, each with the most
  // particles. Each copy is a hypothesis; the walk then rules them out one by one.
  const LedMap& map = vlc_->map();
  int best = -1;
  std::size_t copies = std::numeric_limits<std::size_t>::max();
  for (std::size_t i = 0; i < lik.size(); ++i) {
    const int k = lik.term(i).klass;
    if (k < 0 || !lik.ceiling_point(i).allFinite()) continue;
    const std::size_t n = map.classes()[static_cast<std::size_t>(k)].members.size();
    if (n < copies) {
      copies = n;
      best = static_cast<int>(i);
    }
  }
  if (best >= 0) {
    std::vector<Eigen::Vector2d> anchors;
    for (int m : map.classes()[static_cast<std::size_t>(lik.term(static_cast<std::size_t>(best)).klass)].members)
      anchors.push_back(map.leds()[static_cast<std::size_t>(m)].p_inW.head<2>());
    // 0.25 m: a 2 deg tilt error or a 0.1 m height error moves the bearing's ceiling point
    // by under 0.1 m at 2 m; the spread covers it 2.5 times (reasoning, not tuned).
    // Headings: a restart keeps the filter's offset and spreads it over 3 of its sigmas (at
    // least the prior's): after a kidnap in the dark the yaw has drifted unobserved, and a
    // search that does not hold the true heading settles on a wrong copy.
    double yaw_mean = 0.0, yaw_sigma = options_.pf.heading.sigma0_rad;
    if (pf_->initialized()) {
      const HeadingState h = heading_state();
      if (std::isfinite(h.offset_rad)) yaw_mean = h.offset_rad;
      if (std::isfinite(h.sigma_rad)) yaw_sigma = std::max(yaw_sigma, 3.0 * h.sigma_rad);
    }
    pf_->initialize_around(anchors, lik.ceiling_point(static_cast<std::size_t>(best)), 0.25, options_.global_particles,
                           yaw_mean, yaw_sigma);
    stats_.global_searches.back().particles = pf_->size();
    return;
  }
  const Eigen::Vector4d b = map.bounds();
  Eigen::AlignedBox2d region(Eigen::Vector2d(b[0], b[1]), Eigen::Vector2d(b[2], b[3]));
  region.min() -= Eigen::Vector2d::Constant(1.0);  // a camera sees LEDs up to ~1 m beyond the outer row
  region.max() += Eigen::Vector2d::Constant(1.0);
  pf_->initialize_uniform(region, options_.global_particles);
  stats_.global_searches.back().particles = pf_->size();
}

std::optional<PoseHint> FusionEngine::pose_hint(double yaw_offset_rad) {
  if (!filter_->initialized()) return std::nullopt;
  const PlanarEstimate e = filter_->estimate();
  if (!e.p.allFinite() || !e.cov_p.allFinite()) return std::nullopt;
  // The larger axis of the covariance (its largest eigenvalue, closed form for 2x2).
  const double tr = e.cov_p.trace(), det = e.cov_p.determinant();
  const double l_max = 0.5 * tr + std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  return PoseHint{e.p, yaw_offset_rad, std::sqrt(std::max(0.0, l_max))};
}

void FusionEngine::on_fix(const FixSample& s, std::vector<PoseEstimate>& out) {
  if (!s.p_inW.allFinite()) return;
  PositionMeasurement m;
  m.t = s.t;
  m.z = s.p_inW;
  const double sigma = std::isfinite(s.sigma_m) && s.sigma_m > 0 ? s.sigma_m : options_.default_fix_sigma_m;
  m.R = Eigen::Matrix2d::Identity() * sigma * sigma;
  // Without an IMU this is the only prediction there is (constant velocity up to the fix);
  // skipping it left the filter without process noise: it collapsed and gated the fixes.
  predict_to(std::max(s.t, t_filter_));
  apply_position(m);
  if (!have_imu_) emit(s.t, out, true);
}

void FusionEngine::apply_position(const PositionMeasurement& m) {
  const bool was_initialized = filter_->initialized();
  if (!was_initialized) t_filter_ = have_imu_ ? t_imu_ : m.t;
  const std::optional<PlanarEstimate> before =
      was_initialized ? std::optional<PlanarEstimate>(filter_->estimate()) : std::nullopt;
  if (was_initialized) before_correction();
  const CorrectionResult r = filter_->correct(m);
  if (r.accepted) {
    ++stats_.fixes_accepted;
    t_last_fix_ = m.t;
  } else {
    ++stats_.fixes_gated;
  }
  if (r.accepted && !r.reinitialized && before) note_innovation(m.t, m, *before);
  if (r.reinitialized && was_initialized) ++stats_.reinitializations;
}

void FusionEngine::note_innovation(TimeNs t, const PositionMeasurement& m, const PlanarEstimate& before) {
  if (!before.valid) return;
  innovation_bias().add(t, m.z - before.p, before.cov_p + m.R);
}

InnovationBias& FusionEngine::innovation_bias() {
  // Every restart counts in stats_.reinitializations: a new track, whose lag the old one's
  // innovations say nothing of.
  if (restarted_since(innovation_reinits_)) innovation_bias_.reset();
  return innovation_bias_;
}

std::optional<PositionMeasurement> FusionEngine::uwb_start_agreed(const PositionMeasurement& fix) {
  const UwbOptions& o = uwb_->options();
  if (!fix.z.allFinite() || !fix.R.allFinite() || !(fix.R.determinant() > 0.0)) return std::nullopt;
  const auto need = static_cast<std::size_t>(std::max(1, o.start_agreeing_fixes));
  uwb_start_fixes_.push_back(fix);
  while (uwb_start_fixes_.size() > need) uwb_start_fixes_.pop_front();
  if (uwb_start_fixes_.size() < need) return std::nullopt;
  Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
  Eigen::Vector2d info_z = Eigen::Vector2d::Zero();
  for (const PositionMeasurement& m : uwb_start_fixes_) {
    const double move = o.start_speed_mps * std::abs(ns_to_seconds(fix.t - m.t));
    const Eigen::Matrix2d S = fix.R + m.R + Eigen::Matrix2d::Identity() * move * move;
    const Eigen::Vector2d d = fix.z - m.z;
    if (!(d.dot(S.ldlt().solve(d)) <= o.start_gate_chi2)) return std::nullopt;
    const Eigen::Matrix2d Ri = m.R.inverse();
    info += Ri;
    info_z += Ri * m.z;
  }
  PositionMeasurement start = fix;
  start.z = info.ldlt().solve(info_z);
  uwb_start_fixes_.clear();
  return start;
}

void FusionEngine::on_uwb(const UwbSample& s, std::vector<PoseEstimate>& out) {
  const std::optional<UwbRangeLikelihood> lik = uwb_->likelihood(s);
  if (!lik) return;
  std::optional<PositionMeasurement> fix = uwb_->fix(s);
  UwbStats& st = uwb_->stats();
  if (uwb_->options().fixes_only) {  // UWB alone: the fix is the pose
    if (!fix || !fix->z.allFinite()) {
      ++st.no_fix;
      return;
    }
    ++st.fixes_used;
    PoseEstimate p;
    p.t = s.t;
    p.p_BinW = {fix->z.x(), fix->z.y(), device_height_m_};
    if (ahrs_.initialized()) p.yaw = ahrs_.yaw();
    p.sigma_x = std::sqrt(fix->R(0, 0));
    p.sigma_y = std::sqrt(fix->R(1, 1));
    // A fix outside the anchors may be a mirror (issue 16 part 4): the mode says so.
    p.mode = uwb_->last_fix_outside_hull() ? "uwb-outside-anchors" : "uwb";
    out.push_back(std::move(p));
    ++stats_.poses;
    return;
  }
  // Without an IMU (a UWB-only live run) the prediction is constant velocity.
  predict_to(std::max(s.t, t_filter_));
  const bool tight = pf_ && options_.tight_coupling;
  if (!tight || !filter_->initialized()) {
    // Loose coupling (seed B.3 fix, Gaussian weighting as in seed A, S302), the EKF, and
    // the first fix of a tight run.
    if (filter_->initialized()) uwb_->observe(s, filter_->estimate());
    if (fix && !filter_->initialized()) {
      fix = uwb_start_agreed(*fix);  // UwbOptions::start_agreeing_fixes
      if (!fix) {
        ++st.no_fix;
        ++st.start_held;
        return;
      }
    }
    if (fix) {
      const std::uint64_t gated = stats_.fixes_gated;
      apply_position(*fix);
      ++(stats_.fixes_gated > gated ? st.fixes_gated : st.fixes_used);
      if (!have_imu_) emit(s.t, out, true);
    } else {
      ++st.no_fix;
    }
    return;
  }
  // Tight: weigh every particle by this measurement's likelihood (robust NLOS tail).
  // Gate at the mean only to notice a lost track, never to refuse an update: the robust
  // likelihood already discounts outliers.
  const PlanarEstimate e = pf_->estimate();
  uwb_->observe(s, e);  // height and bias from the estimate before this range weighed it
  if (uwb_->nlos(s.anchor)) {  // part 4: an anchor whose recent ranges read long is not weighed
    ++st.nlos_set_aside;
    if (!have_imu_) emit(s.t, out, true);
    return;
  }
  const UwbNoiseModel& nm = uwb_->options().noise;
  const double spread = std::sqrt(std::max(0.0, e.cov_p.trace()));
  const double range_tol = uwb_->options().gate_sigma * std::hypot(nm.range_sigma_m, spread);
  const double bearing_tol = uwb_->options().gate_sigma * nm.aoa_sigma_rad +
                             std::max(0.3, spread) / std::max(0.5, lik->horizontal_distance(e.p.x(), e.p.y()));
  const bool agrees = std::abs(lik->range_residual(e.p.x(), e.p.y())) <= range_tol &&
                      std::abs(lik->bearing_residual(e.p.x(), e.p.y())) <= bearing_tol;
  if (!agrees) {
    ++st.disagreements;
    if (++uwb_disagreements_ >= uwb_->options().max_consecutive_disagreements && fix) {
      pf_->initialize(fix->z, fix->R * 4.0);
      ++st.reinitializations;
      ++stats_.reinitializations;
      uwb_disagreements_ = 0;
      t_last_fix_ = s.t;
      return;
    }
  } else {
    uwb_disagreements_ = 0;
    // A range (+ bearing) that agrees: its fix's innovation, for the reported sigma.
    if (fix) note_innovation(s.t, *fix, e);
  }
  before_correction();
  if (pf_->weigh(*lik) && pf_->normalize_and_resample()) {
    ++st.weighed;
    ++stats_.fixes_accepted;
    t_last_fix_ = s.t;
  } else if (fix) {  // every particle underflowed: recover at the fix
    pf_->initialize(fix->z, fix->R * 4.0);
    ++st.reinitializations;
    ++stats_.reinitializations;
  } else {
    ++st.underflow;
  }
  if (!have_imu_) emit(s.t, out, true);
}

void FusionEngine::on_vo_frame(const FrameSample& s) {
  ++vo_stats_.frames;
  const std::optional<FloorMotion> m = vo_->process(s.gray, s.t);
  if (!m || !(m->dt_s > 0.0)) return;
  ++vo_stats_.motions;
  if (!ahrs_.initialized() || !filter_->initialized() || std::abs(m->scale - 1.0) > vo_options_.max_scale_error) {
    ++vo_stats_.rejected;
    return;
  }
  // Heading: visual yaw increments, slowly pulled to the attitude filter's yaw.
  const double yaw_ahrs = ahrs_.yaw();
  if (!vo_heading_valid_) {
    vo_heading_ = yaw_ahrs - m->dyaw_rad;  // heading before this interval
    vo_heading_valid_ = true;
  }
  vo_heading_ += m->dyaw_rad;
  if (vo_options_.heading_tau_s > 0.0) {
    const double a = std::min(1.0, m->dt_s / vo_options_.heading_tau_s);
    vo_heading_ += a * std::remainder(yaw_ahrs - vo_heading_, 2.0 * 3.14159265358979323846);
  }
  // The body moved d_inB over the frame interval: into the world with the yaw at its middle.
  const double yaw = vo_heading_ - 0.5 * m->dyaw_rad;
  const Eigen::Vector2d d_inW(std::cos(yaw) * m->d_inB.x() - std::sin(yaw) * m->d_inB.y(),
                              std::sin(yaw) * m->d_inB.x() + std::cos(yaw) * m->d_inB.y());
  VelocityMeasurement v;
  v.t = s.t;
  v.v = d_inW / m->dt_s;
  v.R = Eigen::Matrix2d::Identity() * vo_options_.velocity_sigma_mps * vo_options_.velocity_sigma_mps;
  predict_to(std::max(s.t, t_filter_));
  if (filter_->correct_velocity(v).accepted)
    ++vo_stats_.accepted;
  else
    ++vo_stats_.rejected;
}

void FusionEngine::emit(TimeNs t, std::vector<PoseEstimate>& out, bool force) {
  if (!filter_->initialized() || uwb_->options().fixes_only) return;
  if (!force && emitted_ && options_.output_rate_hz > 0 &&
      ns_to_seconds(t - t_last_emit_) < 1.0 / options_.output_rate_hz - 1e-6)
    return;
  const PlanarEstimate e = filter_->estimate();
  if (!e.valid) return;  // never emit NaN
  PoseEstimate p;
  p.t = t;
  p.p_BinW = {e.p.x(), e.p.y(), device_height_m_};
  if (uwb_->estimates_height() || vertical_) {  // issue 16 part 3: z learnt from the ranges or the camera
    const auto [z, sigma_z] = height_now();
    p.p_BinW.z() = z;
    p.sigma_z = sigma_z;
  }
  if (ahrs_.initialized()) {
    // The fused yaw: the AHRS's plus the filter's offset (issue 11); its sigma.
    const HeadingState h = heading_state();
    p.yaw = std::remainder(ahrs_.yaw() + h.offset_rad, 2.0 * 3.14159265358979323846);
    p.sigma_yaw = h.sigma_rad;
    p.roll = ahrs_.roll();
    p.pitch = ahrs_.pitch();
  }
  // The attitude's tilt error is a bias that lasts seconds (an accelerometer bias over g:
  // 0.3-0.6 deg on the simulator's IMUs), not the per-frame noise the likelihood assumes
  // of it: it moves every VLC fix by dz x tilt the same way, so no spread of the filter can
  // hold it. While the camera anchors the position (a VLC correction within 1 s) the
  // reported sigma carries FusionOptions::tilt_floor_share x dz x attitude_sigma_rad besides
  // the filter's spread, and is at least the whole dz x attitude_sigma_rad per axis
  // (FusionOptions::tilt_floor_min). Found on floor-plan seed 21 (0.5 / 0.6 deg roll / pitch
  // bias: 37 % of the poses within their 95 % ellipse, 1.4 cm sigma against 3.7 cm error);
  // the filter itself is unchanged.
  double tilt_share2 = 0.0, tilt_min2 = 0.0;
  if (vlc_ && t_last_vlc_ && t >= *t_last_vlc_ && ns_to_seconds(t - *t_last_vlc_) < 1.0) {
    const double tilt = vlc_ceiling_distance() * options_.attitude_sigma_rad;
    tilt_share2 = options_.tilt_floor_share * options_.tilt_floor_share * tilt * tilt;
    if (options_.tilt_floor_min) tilt_min2 = tilt * tilt;
  }
  // The fixes' persistent innovation (FusionOptions::innovation_bias): a lag the filter's
  // spread does not know of.
  const Eigen::Vector2d lag2 = innovation_bias().extra_variance();
  if (lag2.x() > e.cov_p(0, 0) || lag2.y() > e.cov_p(1, 1)) ++stats_.poses_lag_widened;  // the lag dominates
  stats_.max_lag_sigma_m = std::max(stats_.max_lag_sigma_m, std::sqrt(lag2.maxCoeff()));
  p.sigma_x = std::sqrt(std::max(std::max(0.0, e.cov_p(0, 0)) + tilt_share2, tilt_min2) + lag2.x());
  p.sigma_y = std::sqrt(std::max(std::max(0.0, e.cov_p(1, 1)) + tilt_share2, tilt_min2) + lag2.y());
  p.n_eff = e.n_eff;
  p.leds = last_leds_;
  p.motion = motion_regime_name(motion_.regime());
  // SPEC.md's modes: re-initialised (for 1 s after the filter restarted around a fix), lost
  // (the last corrections disagreed with the filter: it is being gated towards a restart),
  // tracking (an absolute correction within the last second), else dead-reckoning.
  if (restarted_since(reinits_seen_)) t_last_reinit_ = t;
  if (t_last_reinit_ && ns_to_seconds(t - *t_last_reinit_) < 1.0)
    p.mode = "re-initialised";
  else if (consecutive_gated_ >= kLostAfterGated || uwb_disagreements_ >= kLostAfterGated ||
           (pf_ && pf_->localising()))  // a global search over a reuse map: not found yet
    p.mode = "lost";
  else
    p.mode = ns_to_seconds(t - t_last_fix_) < 1.0 ? "tracking" : "dead-reckoning";
  out.push_back(std::move(p));
  ++stats_.poses;
  t_last_emit_ = t;
  emitted_ = true;
  if (cloud_observer_ && pf_ && pf_->size() > 0 && cloud_points_ > 0) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_cloud_ >= cloud_interval_) {
      last_cloud_ = now;
      const std::size_t stride = std::max<std::size_t>(1, pf_->size() / cloud_points_);
      std::vector<Eigen::Vector2d> cloud;
      cloud.reserve(cloud_points_ + 1);
      for (std::size_t i = 0; i < pf_->size(); i += stride) cloud.push_back(pf_->position(i));
      cloud_observer_(cloud);
    }
  }
}

}  // namespace luxloc
