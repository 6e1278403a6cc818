#pragma once
// How the fusion uses UWB (`luxloc run --uwb-*`, docs/UWB_VO_CALIB.md).
#include "core/uwb/height_bias_filter.hpp"
#include "core/uwb/multilateration.hpp"
#include "core/uwb/uwb_noise_model.hpp"

namespace luxloc {

// Online estimation of a nuisance state (`run --uwb-height`, `--uwb-bias`): automatic turns
// it on where the configured anchors observe it (UwbFrontend's constructor says when).
enum class UwbOnline { off, on, automatic };

struct UwbOptions {
  bool enabled = true;
  UwbNoiseModel noise;
  // Ranges without AOA are grouped for multilateration (loose coupling, initialisation,
  // the EKF) when their time stamps lie within this window.
  double group_window_s = 0.05;
  MultilaterationOptions multilateration;
  // Tight coupling (particle filters): a measurement whose residual at the filter's mean
  // exceeds this many sigma (range sigma plus the filter's spread) counts as a
  // disagreement; this many in a row re-initialise the filter at the next fix (lost track).
  double gate_sigma = 6.0;
  int max_consecutive_disagreements = 15;
  // UWB alone: output every UWB position fix (seed B.3 / multilateration) as the pose,
  // no filter (the "UWB alone" baseline of the figures).
  bool fixes_only = false;
  // Issue 16 parts 1 and 3: the device height and per-anchor range biases learnt while
  // running (core/uwb/height_bias_filter.hpp), not in --uwb-alone (the plain baseline).
  UwbOnline height = UwbOnline::automatic;
  UwbOnline bias = UwbOnline::automatic;
  HeightBiasOptions online;
};

}  // namespace luxloc
