#include "core/sim/simulator.hpp"

#include <cmath>
#include <stdexcept>

#include "core/sim/seeding.hpp"

namespace luxloc::sim {

Simulator::Simulator(Scenario scenario, SimOptions options) : scenario_(std::move(scenario)), opt_(std::move(options)) {
  duration_s_ = opt_.duration_s > 0.0 ? opt_.duration_s : scenario_.duration_s;
  if (!std::isfinite(duration_s_) || !(opt_.fps > 0.0) || !std::isfinite(opt_.fps) || !(opt_.imu_rate_hz > 0.0) ||
      !std::isfinite(opt_.imu_rate_hz) || !(opt_.frame_offset_s >= 0.0))
    throw std::invalid_argument("simulator: duration, fps and imu rate must be finite and > 0");
  if (!scenario_.trajectory) throw std::invalid_argument("simulator: scenario has no trajectory");
  std::mt19937_64 bias_rng = make_rng(opt_.seed, RandomStream::imu_biases);
  std::mt19937_64 scale_rng = make_rng(opt_.seed, RandomStream::imu_scale);
  biases_ = draw_imu_biases(opt_.imu, bias_rng, scale_rng);
  field_ = make_magnetic_field(opt_.mag_disturbance, opt_.imu.mag_field_inW, *scenario_.trajectory, duration_s_);
  // Each LED's square wave starts at a random point of its period (unsynchronised drivers).
  std::mt19937_64 phase_rng = make_rng(opt_.seed, RandomStream::led_phases);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Led& l : scenario_.map.leds()) phases_s_.push_back(unit(phase_rng) / l.freq_hz);
  if (scenario_.floor_camera)  // the room plus a 1.5 m margin (beyond a 1 m-high camera's view), 3 mm texels
    floor_ = std::make_shared<FloorRenderer>(scenario_.camera, -1.5, -1.5, scenario_.room_x_m + 3.0,
                                             scenario_.room_y_m + 3.0, 0.003, opt_.seed);
}

std::size_t Simulator::imu_count() const {
  // k / rate < duration, robust to rounding (90 s at 100 Hz -> 9000 samples).
  return static_cast<std::size_t>(std::ceil(duration_s_ * opt_.imu_rate_hz - 1e-9));
}

std::vector<Eigen::Vector3d> Simulator::gyro_bias_track() const {
  // b(t_k+1) = b(t_k) + sigma_rw sqrt(dt) n_k, from a stream of its own (no draw without a walk).
  std::vector<Eigen::Vector3d> track(imu_count(), biases_.gyro);
  const double step = opt_.imu.gyro_bias_rw_rps_sqrt_s * std::sqrt(1.0 / opt_.imu_rate_hz);
  if (!(step > 0.0)) return track;
  std::mt19937_64 rng = make_rng(opt_.seed, RandomStream::imu_bias_walk);
  std::normal_distribution<double> n(0.0, step);
  for (std::size_t k = 1; k < track.size(); ++k) {
    const double x = n(rng), y = n(rng), z = n(rng);
    track[k] = track[k - 1] + Eigen::Vector3d(x, y, z);
  }
  return track;
}

std::vector<ImuSample> Simulator::imu_samples() const {
  std::mt19937_64 rng = make_rng(opt_.seed, RandomStream::imu_noise);
  const std::vector<Eigen::Vector3d> bias = gyro_bias_track();
  std::vector<ImuSample> out;
  out.reserve(imu_count());
  ImuBiases b = biases_;
  for (std::size_t k = 0; k < imu_count(); ++k) {
    const BodyState s = truth(imu_time_s(k));
    b.gyro = bias[k];
    out.push_back(field_.disturbed() ? synthesize_imu(s, opt_.imu, b, rng, field_.at(s.p_BinW, s.t))
                                     : synthesize_imu(s, opt_.imu, b, rng));
  }
  return out;
}

std::size_t Simulator::frame_count() const {
  return static_cast<std::size_t>(std::floor(duration_s_ * opt_.fps + 1e-9));
}

bool Simulator::lights_on(double t_s) const {
  for (const Blackout& b : opt_.blackouts)
    if (b.contains(t_s)) return false;
  return true;
}

RenderedFrame Simulator::render(std::size_t k) const {
  const double t0 = frame_time_s(k);
  if (floor_) {
    std::mt19937_64 rng = make_rng(opt_.seed, RandomStream::frame, k);
    RenderedFrame f;
    f.gray = floor_->render(scenario_.trajectory->state(t0 + 0.5 * scenario_.camera.exposure_s).T_BtoW(), rng,
                            opt_.render.read_noise_dn);
    return f;
  }
  RenderOptions ro = opt_.render;
  ro.lights_on = ro.lights_on && lights_on(t0);
  std::mt19937_64 rng = make_rng(opt_.seed, RandomStream::frame, k);
  const Trajectory& traj = *scenario_.trajectory;
  const PoseAt pose_at = [&traj](double t) { return traj.state(t).T_BtoW(); };
  return render_frame(scenario_.camera, scenario_.map, pose_at, t0, ro, rng, phases_s_);
}

std::vector<SimUwbMeasurement> Simulator::uwb_measurements() const {
  return synthesize_uwb(*scenario_.trajectory, scenario_.anchors, scenario_.uwb, duration_s_, opt_.seed);
}

}  // namespace luxloc::sim

namespace luxloc::sim {

std::vector<UwbAnchorBias> Simulator::uwb_biases() const {
  return draw_uwb_biases(scenario_.anchors, scenario_.uwb, opt_.seed);
}

}  // namespace luxloc::sim
