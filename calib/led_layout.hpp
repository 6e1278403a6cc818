#pragma once
// Light positions for frequency planning (`luxloc calib ledmap plan`, issue 14): where the
// LEDs of a floor are, before any of them has a frequency. Three sources:
//   - a CSV file: header `x,y` or `x,y,z`, optional `id` column, `#` comments
//     (core/common/csv_reader.hpp);
//   - a YAML LED map (SPEC.md "LED map"): ids and positions kept, frequencies ignored (they
//     may be missing, repeated or too close: the plan replaces them), duty, power,
//     half_power_angle_deg kept;
//   - a grid spec `X0:X1:DX,Y0:Y1:DY` (inclusive ranges, metres).
// Every problem is an InputError naming the file (or the option), the line and the field.
#include <optional>
#include <string>
#include <vector>

#include "core/vlc/led_map.hpp"

namespace luxloc {

struct LedLayout {
  std::vector<Led> leds;   // freq_hz 0 (not planned yet); ids unique
  std::string origin;      // the file, or "--grid" for a grid spec
  bool ids_given = false;  // ids come from the input (else 1..n in input order)
  double max_z = 0.0;      // highest LED
};

// Largest layout read: a floor of 10^6 lights is far beyond any building, and a typo in a
// grid spec (a step of 0.001) must not allocate gigabytes.
inline constexpr std::size_t kMaxLayoutLeds = 1000000;
// Largest |x|, |y|, |z| accepted, m: beyond any building (and it keeps cell indices of the
// planner's grids far from overflow).
inline constexpr double kMaxLayoutCoordinate = 1e6;

// CSV or YAML by the file's extension (.csv; .yaml / .yml). `ceiling_z`: the height of LEDs
// whose layout gives none (a CSV without a z column or with an empty z, a YAML entry without
// z); an InputError when one has none and ceiling_z is not set.
LedLayout read_led_layout(const std::string& path, std::optional<double> ceiling_z);
LedLayout read_led_layout_csv(const std::string& path, std::optional<double> ceiling_z);
LedLayout read_led_layout_yaml(const std::string& path, std::optional<double> ceiling_z);
// `X0:X1:DX,Y0:Y1:DY`: x = X0, X0 + DX, ... up to X1 (inclusive, within 1e-9 of a step),
// rows in y, all at ceiling_z (required). Ids 1..n row by row.
LedLayout grid_led_layout(const std::string& spec, std::optional<double> ceiling_z);

// The densest spot of a layout for a conflict distance D: the most LEDs within D / 2 of one
// LED (that LED included). They are pairwise closer than D, so no two can share a class:
// a lower bound on the classes any plan needs, found in O(n) (a grid of cell D / 2) before
// the planner's O(n (3D)^2 density) neighbour lists are built.
struct LayoutDensity {
  int leds_within = 0;  // the bound
  int centre = -1;      // index into LedLayout::leds of that LED
};
LayoutDensity densest_cluster(const LedLayout& layout, double conflict_distance_m);

}  // namespace luxloc
