#pragma once
// One LED blob found in a rolling-shutter frame and what the stripe decoder made of it
// (SEEDS.md A, S203: segment, count the stripes -> frequency -> ID -> known position).
#include <Eigen/Core>
#include <string>

namespace luxloc {

struct LedObservation {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // blob centre (envelope, not bright stripes), distorted pixels
  double row_span = 0.0;       // rows covered by the blob
  double period_rows = 0.0;    // estimated stripe period, sub-row precision
  double period_sigma_rows = 0.0;  // 1-sigma of period_rows
  double freq_hz = 0.0;        // 1 / (period_rows * row_time)
  int freq_class = -1;         // into LedMap::classes(); -1 = rejected
  int led_index = -1;          // into LedMap::leds(); -1 = rejected, or a reused frequency (which copy: the position says)
  int led_id = -1;
  double confidence = 0.0;     // 0..1
  double intensity_sum = 0.0;  // sum of (pixel - background) over the blob: received power for RSS
  double on_fraction = 1.0;    // mean stripe on-fraction over the blob (intensity_sum / on_fraction ~ LED always on)
  double radius_px = 0.0;      // equivalent radius
  bool radius_from_envelope = false;  // radius_px is the envelope ellipse's (else from the bright-pixel count)
  bool touches_border = false;  // cut by the image border: centre and power are biased
  bool saturated = false;       // clipped pixels in the blob: intensity_sum underestimates the power
  // Empty when accepted, else one of: "too narrow", "overlapping blobs", "too few rows",
  // "no stripes", "ambiguous frequency", "no map match".
  std::string reject_reason;

  // Identified: the frequency names one LED of the map.
  bool accepted() const { return led_index >= 0 && reject_reason.empty(); }
  // The frequency class is known (one LED, or one of the copies of a reused frequency).
  bool classified() const { return freq_class >= 0 && reject_reason.empty(); }
  // Received power estimate for the RSS model (SEEDS A S201): the blob's energy had the
  // LED been on for the whole exposure of every row.
  double received_power() const { return on_fraction > 1e-6 ? intensity_sum / on_fraction : intensity_sum; }
};

}  // namespace luxloc
