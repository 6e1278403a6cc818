#pragma once
// The LED map (SPEC.md "LED map"): id, blink frequency and world position of each
// ceiling LED. The frequency is the LED's identity (SEEDS.md A, S202).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace luxloc {

struct Led {
  int id = 0;
  double freq_hz = 0.0;
  Eigen::Vector3d p_inW = Eigen::Vector3d::Zero();
  double duty = 0.5;                   // fraction of the period the LED is on
  double half_power_angle_deg = 60.0;  // Lambertian semi-angle phi_1/2 (m = 1 at 60 deg)
  double power = 1.0;                  // relative intensity for the RSS model
  double diameter_m = 0.15;            // optional, used by the simulator only
};

struct LedMapOptions {
  // Two LEDs whose frequencies differ by less than this relative amount cannot be told
  // apart by the stripe decoder; such a map is rejected.
  double min_relative_separation = 0.02;
};

class LedMap {
 public:
  LedMap() = default;
  // Validates (unique ids, freq > 0, separable frequencies); throws InputError naming
  // `origin` (a file path), the LED and the field.
  LedMap(std::vector<Led> leds, std::string origin, const LedMapOptions& options = {});

  // Reads an OpenCV FileStorage YAML map; throws InputError on any unusable content.
  static LedMap load(const std::string& path, const LedMapOptions& options = {});
  // Writes the map in the same form (exactly what load() reads back).
  void save(const std::string& path) const;

  const std::vector<Led>& leds() const { return leds_; }
  std::size_t size() const { return leds_.size(); }
  bool empty() const { return leds_.empty(); }
  const Led* find_id(int id) const;

  struct FrequencyMatch {
    int index = -1;            // into leds(), -1 when no LED within tolerance
    double rel_error = 1e9;    // |f - f_led| / f_led of the best candidate
    double runner_up = 1e9;    // same for the second best (ambiguity margin)
  };
  // Nearest LED by relative frequency error; index = -1 if beyond rel_tolerance.
  FrequencyMatch match_frequency(double f_hz, double rel_tolerance) const;

  // Smallest relative gap between any two frequencies (inf for < 2 LEDs).
  double min_relative_separation() const;

 private:
  std::vector<Led> leds_;
};

}  // namespace luxloc
