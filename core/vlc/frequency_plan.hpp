#pragma once
// Frequency planning for a building-scale LED map (issue 14, `luxloc calib ledmap plan`):
// which blink frequencies a camera can tell apart, and which LED gets which frequency so
// that no two LEDs of one class are ever in one image.
//
// 1. The band (frequency_band): low end from the stripe count a small, distant blob must
//    show, high end from the stripe contrast left after the exposure averages the square
//    wave and from the period in rows at the row time.
// 2. The assignment (plan_frequency_classes): a graph colouring of the conflict graph
//    (LEDs closer than the co-visibility distance conflict). DSatur finds how many classes
//    are needed; with more classes than that, a binary search finds the largest reuse
//    distance DSatur can still colour, and seeded random recolouring that keeps it breaks
//    the lattice's period, so the pattern does not repeat. A periodic tiling would alias for ever: a particle filter
//    started without a prior could never tell one tile from the next (translational_alias
//    measures that).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vlc/camera_model.hpp"

namespace luxloc {

struct FrequencyBandOptions {
  // Fundamental of a 50 % square wave averaged over exposure T keeps |sinc(f T)| of its
  // contrast (FIELD_NOTES: 0.64 at f T = 0.5). 0.5 (f T <= 0.6): half the contrast, which
  // the decoder's min_contrast_dn (16 DN) still clears on an LED that reaches ~100 DN.
  double min_contrast = 0.5;
  // Shortest stripe period in rows: the decoder resolves 2 (StripeDecoder's
  // min_period_rows); 4 leaves room for the blur of a real lens and Bayer demosaicing.
  double min_period_rows = 4.0;
  // Stripe periods a blob must span to be decoded (StripeDecoderOptions::min_periods 1.75).
  double min_periods = 1.75;
  // Relative step between neighbouring classes: LedMapOptions' 2 % separation times 1.5,
  // so the decoder's tolerance (0.45 x the gap) exceeds the ~0.5 % frequency error of a
  // blob of two periods (docs/VLC.md) with a margin.
  double relative_step = 0.03;
};

struct FrequencyBand {
  double f_min_hz = 0.0, f_max_hz = 0.0;
  double relative_step = 0.03;
  int capacity = 0;          // classes that fit at relative_step
  double blob_rows = 0.0;    // rows of the design blob (the f_min limit)
  std::string high_limit;    // "contrast" or "row time": what sets f_max
};

// The band for LEDs of `led_diameter_m` on a ceiling dz_m above the camera. The design
// blob is an LED at the image's half-diagonal angle of a level camera: nearer to the
// centre the blob is larger and shows more periods.
FrequencyBand frequency_band(const CameraModel& camera, double dz_m, double led_diameter_m,
                             const FrequencyBandOptions& options = {});
// k frequencies spread geometrically over the whole band (the widest gaps k allows).
std::vector<double> spread_frequencies(const FrequencyBand& band, int k);

struct FrequencyPlanOptions {
  int classes = 0;             // 0: max(needed, min(band capacity, 12)) (the caller decides)
  std::uint64_t seed = 1;
  int attempts = 4;        // DSatur runs (random tie-breaks) per tried reuse distance
  // Random recolouring sweeps that keep the reuse distance. 10: on 24x12 and 60x30 grids
  // of 12 classes (seeds 1-3) 4 sweeps sometimes had to give up a step of reuse distance
  // (5.6 m instead of 7.1 m) to get the alias fraction under max_alias; 10 never did, and
  // 20-40 changed nothing measurable.
  int shuffle_passes = 10;
  // Largest accepted translational alias fraction (see translational_alias): 0.3, about
  // three times the 1/12 of an unstructured 12-class colouring; a particle filter's copies
  // of a hypothesis then disagree on 70 % of the LEDs they pass (chosen by reasoning, then
  // checked: on 24x12 and 40x40 grids this costs one or two steps of reuse distance).
  double max_alias = 0.3;
};

struct FrequencyPlan {
  std::vector<int> class_of;        // per input position, 0 .. classes-1
  int classes_needed = 0;           // DSatur's count
  int classes = 0;                  // used
  double conflict_distance_m = 0.0;
  double min_reuse_distance_m = 0.0;  // smallest distance between two LEDs of one class
  double alias_fraction = 0.0;      // translational_alias of the result
  Eigen::Vector2d alias_shift = Eigen::Vector2d::Zero();
};

// Colours positions (floor plane) so that two of one class are >= conflict_distance_m
// apart. Throws std::invalid_argument when options.classes is below what is needed.
FrequencyPlan plan_frequency_classes(const std::vector<Eigen::Vector2d>& positions, double conflict_distance_m,
                                     const FrequencyPlanOptions& options = {});

struct AliasReport {
  double fraction = 0.0;  // of the LEDs whose shifted position is an LED, the share of the same class
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  int overlap = 0;        // LEDs that land on an LED under that shift
};
// The worst translation (up to max_shift_m) that maps LEDs onto LEDs of the same class:
// 1.0 for a periodic tiling, about 1/classes for an unstructured one. Translations that
// overlap fewer than max(20, n/10) LEDs are not counted.
AliasReport translational_alias(const std::vector<Eigen::Vector2d>& positions, const std::vector<int>& class_of,
                                double max_shift_m, double tolerance_m = 0.1);

}  // namespace luxloc
