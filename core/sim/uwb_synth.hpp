#pragma once
// Synthetic UWB measurements (docs/UWB_VO_CALIB.md "Simulator"): every 1/rate_hz, for each
// anchor, the true 3-D distance anchor -> device plus noise (time of flight, c0 * tau) and,
// with with_aoa, the world bearing of the device seen from the anchor plus noise (SEEDS.md
// B.3's theta). With probability nlos_probability a measurement is non-line-of-sight: the
// range gains a positive bias (nlos_bias_min_m + an exponential of mean
// nlos_bias_mean_m) and the bearing points somewhere else (nlos_aoa_sigma_rad).
// The draws come from their own stream (seeding.hpp): adding UWB to a scenario changes no
// other file of the session.
#include <cstdint>
#include <vector>

#include "core/common/samples.hpp"
#include "core/common/session_config.hpp"
#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

struct UwbSimOptions {
  double rate_hz = 10.0;
  double offset_s = 0.003;  // first measurement (radio and IMU clocks differ)
  bool with_aoa = true;
  double range_sigma_m = 0.10;
  double aoa_sigma_rad = 0.05;  // ~3 deg
  double nlos_probability = 0.05;
  double nlos_bias_min_m = 0.3;
  double nlos_bias_mean_m = 0.9;  // of the exponential part
  double nlos_aoa_sigma_rad = 0.3;
  // Issue 16: ranges as uncalibrated radios deliver them. Each anchor's range is offset by
  // a bias drawn once per run, uniform in [bias_min_m, bias_max_m] (antenna delay: mostly
  // short), from a stream of its own; equal bounds draw nothing (the historic sessions).
  double bias_min_m = 0.0, bias_max_m = 0.0;
  // And scaled: measured = scale * true + bias, scale = 1 + N(0, scale_sigma) per anchor
  // (`sim --uwb-scale`; 0: 1 exactly). A clock offset gives only ~2e-5; what real kits show
  // as a slope of up to 1-2 % is a bias that changes with distance (received power), which
  // a line fits to first order.
  double scale_sigma = 0.0;
  // One anchor behind an obstacle during [blocked_from_s, blocked_to_s): all its ranges
  // there are NLOS (0: none).
  int blocked_anchor = 0;
  double blocked_from_s = 0.0, blocked_to_s = 0.0;
  // Two-way ranging takes turns: anchor i of N answers i / (N rate) after the epoch (false:
  // all anchors at the epoch, the historic timing).
  bool stagger = false;
};

struct UwbAnchorBias {
  int anchor = 0;
  double bias_m = 0.0;
  double scale = 1.0;
};

struct SimUwbMeasurement {
  UwbSample sample;
  bool nlos = false;
  double true_range_m = 0.0;
};

// The per-anchor range biases and scales of a run (empty when the options draw neither).
std::vector<UwbAnchorBias> draw_uwb_biases(const std::vector<UwbAnchor>& anchors, const UwbSimOptions& options,
                                           std::uint64_t seed);

std::vector<SimUwbMeasurement> synthesize_uwb(const Trajectory& trajectory, const std::vector<UwbAnchor>& anchors,
                                              const UwbSimOptions& options, double duration_s, std::uint64_t seed);

}  // namespace luxloc::sim
