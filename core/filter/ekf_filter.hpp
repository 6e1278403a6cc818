#pragma once
// Extended Kalman filter over [px, py, vx, vy] (SEEDS.md C.6): constant-velocity
// prediction driven by the IMU's world-frame acceleration as a control input, position
// updates (VLC / UWB fixes) and velocity updates (IMU-derived), each in Joseph form with
// Mahalanobis gating. The process model is the particle filter's, linear: with
// d = exp(-dt / tau) (velocity decay, 1 when tau <= 0 = seed C's pure constant velocity)
//   v' = d (v + a dt) + w,   p' = p + dt (v + v') / 2,   w ~ N(0, q dt),
// so the EKF is the particle filter's Gaussian special case (exact, no linearisation
// error here; "extended" for the interface's sake and later non-linear updates).
#include <Eigen/Core>

#include "core/filter/planar_filter.hpp"

namespace luxloc {

struct EkfOptions {
  double accel_noise_psd = 0.5;  // q, m^2/s^3 (as ParticleFilterOptions)
  double velocity_tau_s = 3.0;   // <= 0: pure constant velocity
  double max_speed = 3.0;        // m/s: the velocity state is clamped above
  double init_speed_sigma = 0.3; // m/s
  int max_consecutive_rejections = 8;  // then re-initialise at the fix (lost track)
  // Caps on the covariance diagonal (m^2, (m/s)^2): a long outage cannot overflow it.
  double max_position_variance = 1e4;
  double max_velocity_variance = 100.0;
};

class EkfFilter final : public PlanarFilter {
 public:
  using Vector4 = Eigen::Matrix<double, 4, 1>;
  using Matrix4 = Eigen::Matrix<double, 4, 4>;

  explicit EkfFilter(const EkfOptions& options = {}) : options_(options) {}

  void initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) override;
  bool initialized() const override { return initialized_; }
  void predict(const MotionInput& u) override;
  CorrectionResult correct(const PositionMeasurement& m) override;
  CorrectionResult correct_velocity(const VelocityMeasurement& m) override;
  PlanarEstimate estimate() const override;

  const Vector4& state() const { return x_; }
  const Matrix4& covariance() const { return P_; }
  const EkfOptions& options() const { return options_; }
  std::uint64_t reinit_count() const { return reinits_; }
  std::uint64_t rejected_count() const { return rejected_; }

 private:
  // Joseph-form update with H selecting rows [row, row + 2) of the state.
  CorrectionResult update(int row, const Eigen::Vector2d& z, const Eigen::Matrix2d& R, double gate);
  void condition();  // symmetric, positive diagonal, capped

  EkfOptions options_;
  Vector4 x_ = Vector4::Zero();
  Matrix4 P_ = Matrix4::Identity();
  bool initialized_ = false;
  int consecutive_rejections_ = 0;
  std::uint64_t reinits_ = 0, rejected_ = 0;
};

}  // namespace luxloc
