#pragma once
// The LED map (SPEC.md "LED map"): id, blink frequency and world position of each
// ceiling LED. The frequency identifies a *frequency class* (SEEDS.md A, S202): a room map
// gives every LED a class of its own; a building map reuses frequencies (issue 14), and
// the LEDs of one class are told apart by position (the filter's association,
// core/vlc/led_association.hpp), which needs them far enough apart that the camera never
// sees two at once (core/vlc/led_visibility.hpp checks that against a camera).
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
  double diameter_m = 0.15;            // optional: the simulator draws it; the camera height measures with it
  bool diameter_known = true;          // false: the map file gave none (0.15 is a placeholder)
};

struct LedMapOptions {
  // Two LEDs whose frequencies differ by less than this relative amount cannot be told
  // apart by the stripe decoder; such a map is rejected, unless they are copies.
  double min_relative_separation = 0.02;
  // Frequencies within this relative amount are copies of one class (frequency reuse).
  // 0.1 %: a twentieth of the separation, well inside the decoder's period resolution, so
  // a copy and a distinct class can never be confused; a gap between the two limits is
  // rejected as neither.
  double same_class_tolerance = 0.001;
};

// The LEDs sharing one frequency (one member in a map without reuse).
struct FrequencyClass {
  double freq_hz = 0.0;       // mean of the members' frequencies
  std::vector<int> members;   // indices into LedMap::leds()
  double mean_z = 0.0;        // mean ceiling height of the members (association ray plane)
};

class LedMap {
 public:
  // Largest |x|, |y|, |z| of an LED the map accepts, m.
  static constexpr double kMaxCoordinateM = 1e5;
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
    int klass = -1;            // into classes(), -1 when no class within tolerance
    int index = -1;            // into leds(): the class's LED when it has one member, else -1
    double rel_error = 1e9;    // |f - f_led| / f_led of the best candidate
    double runner_up = 1e9;    // same for the second best (ambiguity margin)
  };
  // Nearest frequency class by relative frequency error: `klass` = -1 if beyond
  // rel_tolerance; `index` = the LED when the class has a single member, else -1 (a reused
  // frequency: the position tells which copy).
  FrequencyMatch match_frequency(double f_hz, double rel_tolerance) const;

  // Smallest relative gap between two frequency classes (inf for < 2 classes).
  double min_relative_separation() const;

  const std::vector<FrequencyClass>& classes() const { return classes_; }
  int class_of(std::size_t led_index) const { return class_of_[led_index]; }
  // True when some frequency is shared by two or more LEDs.
  bool reuses_frequencies() const { return classes_.size() < leds_.size(); }
  // Smallest horizontal distance between two LEDs of one class (inf without reuse).
  double min_reuse_distance_m() const { return min_reuse_distance_m_; }
  // Floor-plane bounding box of the LEDs (x0, y0, x1, y1).
  Eigen::Vector4d bounds() const { return bounds_; }

 private:
  void build_classes(const std::string& origin, const LedMapOptions& options);

  std::vector<Led> leds_;
  std::vector<FrequencyClass> classes_;
  std::vector<int> class_of_;
  double min_reuse_distance_m_ = 0.0;
  Eigen::Vector4d bounds_ = Eigen::Vector4d::Zero();
};

}  // namespace luxloc
