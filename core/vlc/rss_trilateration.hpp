#pragma once
// Position from received signal strength (SEEDS.md A, S201 with the corrected formula, and
// S203's trilateration).
//
// Lambertian channel, receiver facing up and LED facing down, m = 1:
//   P_r = C P_t h^2 / d^4   =>   d = (C P_t h^2 / P_r)^(1/4),   r = sqrt(d^2 - h^2)
// h = vertical distance receiver -> LED plane, d = 3-D distance, r = horizontal distance,
// C a constant folding the receiver area, pi and the camera's gain (calibrated).
// Here P_r is a blob's intensity_sum over its stripe on-fraction (LedObservation::
// received_power) and P_t the map's relative LED power.
//
// The fix: S203's circles (x_i - x)^2 + (y_i - y)^2 = r_i^2 linearised (differences of the
// equations) for a start, then Gauss-Newton on the log received powers (the noise of a
// power is relative, so log residuals are the natural least squares); with C unknown it is
// solved jointly (x, y, log C) from >= 4 LEDs (3 leave no redundancy).
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/vlc/led_map.hpp"
#include "core/vlc/led_observation.hpp"
#include "core/vlc/vlc_fix.hpp"

namespace luxloc {

// One LED's received power with its world position and relative transmitted power.
struct RssMeasurement {
  Eigen::Vector3d p_LinW = Eigen::Vector3d::Zero();
  double power_t = 1.0;   // P_t, the map's relative power
  double received = 0.0;  // P_r
};

struct RssOptions {
  // Channel constant C (P_r units per unit P_t at h = d = 1 m). NaN: solved with the
  // position (needs >= 4 LEDs). Calibrate with calibrate_rss_constant().
  double C = std::numeric_limits<double>::quiet_NaN();
  double power_rel_sigma = 0.1;  // relative noise of a received power (1 sigma), for the covariance
  int max_iterations = 20;
  bool use_saturated = false;    // clipped blobs under-read the power: skipped by default
  bool use_border_blobs = false;
};

// S201: 3-D distance from the received power; NaN for non-positive inputs.
double rss_distance(double C, double power_t, double h, double received);
// Horizontal distance sqrt(d^2 - h^2) (0 when d < h from noise).
double rss_horizontal_distance(double d, double h);

// Accepted, unclipped observations -> measurements.
std::vector<RssMeasurement> rss_measurements_from(const std::vector<LedObservation>& observations, const LedMap& map,
                                                  const RssOptions& options = {});

// Fix of the receiver (camera) at height z_receiver; R_BtoW/p_CinB, when given, move it to
// the body origin (lever arm). >= 3 LEDs with C known, >= 4 with C unknown.
VlcFix rss_fix(const std::vector<RssMeasurement>& leds, double z_receiver, const RssOptions& options = {},
               const Eigen::Matrix3d& R_BtoW = Eigen::Matrix3d::Identity(),
               const Eigen::Vector3d& p_CinB = Eigen::Vector3d::Zero());

// C estimated by least squares (in log power) from measurements with known receiver
// positions: one sample = (measurement, receiver position).
struct RssSample {
  RssMeasurement led;
  Eigen::Vector3d p_receiver = Eigen::Vector3d::Zero();
};
struct RssCalibration {
  double C = std::numeric_limits<double>::quiet_NaN();
  double rms_log_residual = 0.0;   // RMS of log(P_r / model): the relative power error
  double rms_range_error_m = 0.0;  // RMS error of the S201 distance with the fitted C
  int samples = 0;
  bool valid = false;
};
RssCalibration calibrate_rss_constant(const std::vector<RssSample>& samples);

}  // namespace luxloc
