#pragma once
// Extended Kalman filter over [px, py, vx, vy, k, d] (SEEDS.md C.6), predicted by any of
// the motion models (core/filter/motion_model.hpp), with position updates (VLC / UWB
// fixes) and velocity updates (IMU-derived), each in Joseph form with Mahalanobis gating.
// - strapdown / cv: the particle filter's linear process model on [p, v]: with
//   d = exp(-dt / tau) (velocity decay, 1 when tau <= 0 = seed C's pure constant velocity)
//     v' = d (v + a dt) + w,   p' = p + dt (v + v') / 2,   w ~ N(0, q dt);
// - pdr: v' = k s u(psi + d) (gait speed s, heading psi, u(a) = (cos a, sin a)), the one
//   non-linear model: F is its Jacobian in k and d, so the position fixes calibrate the
//   step-length scale k and the heading offset d as they do the particles'.
// k and d are inert (no correlation, no change) under the other models.
#include <Eigen/Core>

#include "core/filter/motion_model.hpp"
#include "core/filter/planar_filter.hpp"

namespace luxloc {

struct EkfOptions {
  double accel_noise_psd = 0.5;  // q, m^2/s^3 (as ParticleFilterOptions)
  double velocity_tau_s = 3.0;   // <= 0: pure constant velocity
  double max_speed = 3.0;        // m/s: the velocity state is clamped above
  double init_speed_sigma = 0.3; // m/s
  GaitNoise gait;                // pdr: the calibration states k, d
  int max_consecutive_rejections = 8;  // then re-initialise at the fix (lost track)
  // Caps on the covariance diagonal (m^2, (m/s)^2): a long outage cannot overflow it.
  double max_position_variance = 1e4;
  double max_velocity_variance = 100.0;
};

class EkfFilter final : public PlanarFilter {
 public:
  using Vector4 = Eigen::Matrix<double, 4, 1>;
  using Matrix4 = Eigen::Matrix<double, 4, 4>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;

  explicit EkfFilter(const EkfOptions& options = {}) : options_(options) {}

  void initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) override;
  bool initialized() const override { return initialized_; }
  void predict(const MotionInput& u) override;
  CorrectionResult correct(const PositionMeasurement& m) override;
  CorrectionResult correct_velocity(const VelocityMeasurement& m) override;
  PlanarEstimate estimate() const override;

  // [px, py, vx, vy] and its covariance.
  Vector4 state() const { return x_.head<4>(); }
  Matrix4 covariance() const { return P_.topLeftCorner<4, 4>(); }
  // With the gait states [.., k, d].
  const Vector6& full_state() const { return x_; }
  const Matrix6& full_covariance() const { return P_; }
  const EkfOptions& options() const { return options_; }
  std::uint64_t reinit_count() const { return reinits_; }
  std::uint64_t rejected_count() const { return rejected_; }

 private:
  // Joseph-form update with H selecting rows [row, row + 2) of the state.
  CorrectionResult update(int row, const Eigen::Vector2d& z, const Eigen::Matrix2d& R, double gate);
  void condition();  // symmetric, positive diagonal, capped
  void predict_gait(const MotionInput& u);

  EkfOptions options_;
  Vector6 x_ = Vector6::Zero();
  Matrix6 P_ = Matrix6::Identity();
  bool initialized_ = false;
  int consecutive_rejections_ = 0;
  std::uint64_t reinits_ = 0, rejected_ = 0;
};

}  // namespace luxloc
