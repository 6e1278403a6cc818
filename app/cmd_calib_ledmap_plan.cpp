// `luxloc calib ledmap plan` (issue 14): frequencies for a floor of lights. Given where the
// lights are (a CSV or YAML layout, or a grid spec), the ceiling and device heights and the
// camera (row time, exposure, intrinsics), it picks the band the camera separates
// (core/vlc/frequency_plan.hpp: frequency_band), colours the LEDs so that no two of one
// class are ever in one image (plan_frequency_classes: DSatur over the conflict graph, then
// the largest reuse distance and a non-periodic shuffle), writes the map and re-reads it as
// a self-check (LedMap::load, check_frequency_reuse).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "calib/led_layout.hpp"
#include "core/common/input_error.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/frequency_plan.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_visibility.hpp"

namespace luxloc::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Default class count cap. FIELD_NOTES: a webcam separates about 10-15 frequencies per
// camera mode; 12 sits inside that range. More classes lengthen the reuse distance (the
// filter tells copies apart more easily) but narrow the gaps between neighbouring
// frequencies, which the decoder's tolerance has to resolve; fewer shorten the distance.
constexpr int kDefaultClassCap = 12;

struct PlanArgs {
  std::string layout, grid, camera, out;
  std::optional<double> ceiling_z;
  double device_height_m = 1.0;
  double max_tilt_deg = 15.0;
  double led_diameter_m = 0.2;
  double margin_m = 0.25;
  int classes = 0;
  std::uint64_t seed = 1;
};

// The band depends on the row time and the exposure: CameraModel::load falls back to 30 us
// and 100 us when a camera file lacks them, which would plan for a camera that is not there.
CameraModel load_timed_camera(const std::string& path) {
  CameraModel c = CameraModel::load(path);
  const char* hint =
      "missing: the frequency plan depends on it (luxloc calib rowtime measures the row time; the exposure is the "
      "camera mode's)";
  if (!c.row_time_known) throw InputError(path, 0, "row_time_us", hint);
  if (!c.exposure_known) throw InputError(path, 0, "exposure_us", hint);
  return c;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run_plan(const PlanArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  if (a.layout.empty() == a.grid.empty())
    throw InputError("--layout", 0, "--layout",
                     "give exactly one of --layout FILE.csv|FILE.yaml and --grid X0:X1:DX,Y0:Y1:DY");
  if (!(a.max_tilt_deg >= 0.0 && a.max_tilt_deg < 60.0))
    throw InputError("--max-tilt-deg", 0, "--max-tilt-deg", "must be in [0, 60) degrees");
  if (!(a.led_diameter_m > 0.0 && a.led_diameter_m < 5.0))
    throw InputError("--led-diameter", 0, "--led-diameter", "must be in (0, 5) m");
  if (!(a.margin_m >= 0.0 && a.margin_m < 100.0)) throw InputError("--margin", 0, "--margin", "must be in [0, 100) m");
  if (a.classes < 0) throw InputError("--classes", 0, "--classes", "must be >= 0 (0: automatic)");
  if (a.ceiling_z && !std::isfinite(*a.ceiling_z))
    throw InputError("--ceiling-height", 0, "--ceiling-height", "not finite");
  if (!std::isfinite(a.device_height_m))
    throw InputError("--device-height", 0, "--device-height", "not finite");

  const CameraModel camera = load_timed_camera(a.camera);
  const LedLayout layout = a.grid.empty() ? read_led_layout(a.layout, a.ceiling_z) : grid_led_layout(a.grid, a.ceiling_z);
  const std::string source = a.grid.empty() ? a.layout : "grid " + a.grid;

  const double dz = layout.max_z - a.device_height_m;
  if (!(dz > 0.0))
    throw InputError(layout.origin, 0, a.grid.empty() ? "z" : "--ceiling-height",
                     "the highest LED (z " + fmt("%.2f", layout.max_z) + " m) is not above the device (" +
                         fmt("%.2f", a.device_height_m) +
                         " m, --device-height): the camera looks up at the ceiling; check --ceiling-height");
  const double tilt = a.max_tilt_deg * kPi / 180.0;
  const double co_vis = co_visibility_distance_m(camera, dz, tilt);
  const double conflict = co_vis + a.led_diameter_m + a.margin_m;
  // The band at the highest LED: its blob is the smallest, which sets the low end.
  const FrequencyBand band = frequency_band(camera, dz, a.led_diameter_m);

  std::vector<Eigen::Vector2d> positions;
  positions.reserve(layout.leds.size());
  for (const Led& l : layout.leds) positions.emplace_back(l.p_inW.x(), l.p_inW.y());
  const int n = static_cast<int>(positions.size());

  std::printf("calib ledmap plan: %d LEDs (%s), highest at z %.2f m, device at %.2f m: %.2f m below\n", n,
              source.c_str(), layout.max_z, a.device_height_m, dz);
  const std::string top = band.high_limit == "contrast"
                              ? "stripe contrast at the " + fmt("%.0f", camera.exposure_s * 1e6) + " us exposure"
                              : "a stripe period of " + fmt("%.0f", FrequencyBandOptions{}.min_period_rows) +
                                    " rows at " + fmt("%.1f", camera.row_time_s * 1e6) + " us a row";
  std::printf("  band: %.1f - %.1f Hz (bottom: %.2f stripe periods across a %.2f m LED at the image corner, %.1f "
              "rows; top: %s), %d classes fit at %.0f %% steps\n",
              band.f_min_hz, band.f_max_hz, FrequencyBandOptions{}.min_periods, a.led_diameter_m, band.blob_rows,
              top.c_str(), band.capacity, band.relative_step * 100.0);
  std::printf("  conflict distance: %.2f m (two LEDs seen together up to %.2f m apart at %.0f deg tilt, + %.2f m LED "
              "+ %.2f m margin)\n",
              conflict, co_vis, a.max_tilt_deg, a.led_diameter_m, a.margin_m);
  std::fflush(stdout);

  const auto band_too_narrow = [&](const std::string& why) {
    const bool contrast = band.high_limit == "contrast";
    std::string msg = why + ": the band this camera separates holds " + std::to_string(band.capacity) + " classes" +
                      " (" + fmt("%.0f", band.f_min_hz) + " - " + fmt("%.0f", band.f_max_hz) + " Hz at " +
                      fmt("%.0f", band.relative_step * 100) + " % steps; top set by the " + band.high_limit +
                      "). What would help: ";
    msg += contrast ? "a shorter exposure (now " + fmt("%.0f", camera.exposure_s * 1e6) +
                          " us) raises the top of the band; "
                    : "a shorter row time (a camera mode with faster readout) raises the top of the band; ";
    msg += "a lower ceiling or larger LEDs (bigger blobs) lower its bottom; LEDs farther apart, a smaller "
           "--max-tilt-deg or --margin need fewer classes";
    throw InputError(a.camera, 0, contrast ? "exposure_us" : "row_time_us", msg);
  };
  if (band.capacity < 1)
    band_too_narrow("No frequency fits: the lowest a far blob shows enough stripes of (" + fmt("%.0f", band.f_min_hz) +
                    " Hz) is above the highest the camera still sees stripes at (" + fmt("%.0f", band.f_max_hz) +
                    " Hz)");
  if (a.classes > band.capacity)
    band_too_narrow("--classes " + std::to_string(a.classes) + " asks for more classes than fit");

  // The planner's neighbour grids (cell 3 x the conflict distance) span the layout's
  // bounding box: a layout kilometres wide at a small conflict distance would allocate
  // gigabytes of empty cells. 4 million cells (~100 MB) is a 27 km square at 4.6 m.
  {
    Eigen::Vector2d lo = positions.front(), hi = positions.front();
    for (const auto& q : positions) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    const double reach = 3.0 * conflict;
    const double cells = (std::floor((hi.x() - lo.x()) / reach) + 1.0) * (std::floor((hi.y() - lo.y()) / reach) + 1.0);
    if (cells > 4e6)
      throw InputError(layout.origin, 0, "x/y",
                       "the layout spans " + fmt("%.0f", hi.x() - lo.x()) + " m x " + fmt("%.0f", hi.y() - lo.y()) +
                           " m, too wide for the planner at a conflict distance of " + fmt("%.2f", conflict) +
                           " m: plan each building or floor on its own");
  }
  // A bound before the planner's neighbour lists are built (their size grows with the
  // density): LEDs pairwise closer than the conflict distance need a class each.
  const LayoutDensity dense = densest_cluster(layout, conflict);
  if (dense.leds_within > band.capacity || (a.classes > 0 && dense.leds_within > a.classes)) {
    const Led& c = layout.leds[static_cast<std::size_t>(dense.centre)];
    const std::string needs = "the layout needs at least " + std::to_string(dense.leds_within) + " classes (" +
                              std::to_string(dense.leds_within) + " LEDs within " + fmt("%.2f", conflict / 2) +
                              " m of LED id " + std::to_string(c.id) + " at " + fmt("%.2f", c.p_inW.x()) + ", " +
                              fmt("%.2f", c.p_inW.y()) + " m, all closer than " + fmt("%.2f", conflict) +
                              " m to each other)";
    if (dense.leds_within > band.capacity) band_too_narrow("Too many LEDs close together: " + needs);
    throw InputError("--classes", 0, "--classes", std::to_string(a.classes) + " classes are too few: " + needs);
  }

  // The class count: the one asked for, else max(needed, min(capacity, 12)) (and no more
  // classes than LEDs). DSatur's count comes from the planner itself: a first plan at the
  // target count, and only when that is too few a plan at the needed count.
  const int target = a.classes > 0 ? a.classes : std::max(1, std::min({band.capacity, kDefaultClassCap, n}));
  FrequencyPlanOptions po;
  po.seed = a.seed;
  po.classes = target;
  const auto t_plan = std::chrono::steady_clock::now();
  FrequencyPlan plan;
  try {
    plan = plan_frequency_classes(positions, conflict, po);
  } catch (const std::invalid_argument&) {
    po.classes = 0;  // the needed count
    plan = plan_frequency_classes(positions, conflict, po);
    const std::string needs = "the layout needs " + std::to_string(plan.classes_needed) + " classes (LEDs closer than " +
                              fmt("%.2f", conflict) + " m can be in one image)";
    if (a.classes > 0 && plan.classes_needed <= band.capacity)
      throw InputError("--classes", 0, "--classes",
                       std::to_string(a.classes) + " classes are too few: " + needs + "; give --classes " +
                           std::to_string(plan.classes_needed) + " or more (up to " + std::to_string(band.capacity) +
                           "), or 0 for the default");
    if (plan.classes_needed > band.capacity)
      band_too_narrow("Too many LEDs close together: " + needs);
  }
  const double plan_s = seconds_since(t_plan);
  const int k = plan.classes;

  std::vector<int> members(static_cast<std::size_t>(k), 0);
  for (int c : plan.class_of) ++members[static_cast<std::size_t>(c)];
  const std::vector<double> freqs = spread_frequencies(band, k);
  std::printf("  classes: %d needed (DSatur), %d used\n", plan.classes_needed, k);
  std::printf("  min reuse distance: %.2f m (copies of a frequency at least that far apart; conflict %.2f m)\n",
              plan.min_reuse_distance_m, conflict);
  if (plan.alias_fraction > 0.0 || plan.alias_shift.squaredNorm() > 0.0)
    std::printf("  alias fraction: %.3f (worst shift %.1f, %.1f m: the share of LEDs that shift lands on a copy of "
                "their own class)\n",
                plan.alias_fraction, plan.alias_shift.x(), plan.alias_shift.y());
  else
    std::printf("  alias fraction: 0.000 (no shift lands enough LEDs on LEDs: the layout does not repeat)\n");
  std::printf("  frequencies (Hz, LEDs):");
  for (int c = 0; c < k; ++c)
    std::printf("%s %.1f (%d)", c % 6 == 0 && c > 0 ? "\n                         " : "", freqs[static_cast<std::size_t>(c)],
                members[static_cast<std::size_t>(c)]);
  std::printf("\n");
  if (k > 1)
    std::printf("  neighbouring frequencies %.1f %% apart (the map needs >= %.0f %%)\n",
                100.0 * (freqs[1] / freqs[0] - 1.0), 100.0 * LedMapOptions{}.min_relative_separation);

  std::vector<Led> leds = layout.leds;
  for (std::size_t i = 0; i < leds.size(); ++i) {
    leds[i].freq_hz = freqs[static_cast<std::size_t>(plan.class_of[i])];
    leds[i].diameter_m = a.led_diameter_m;
  }
  const auto t_write = std::chrono::steady_clock::now();
  LedMap(std::move(leds), a.out).save(a.out);
  const double write_s = seconds_since(t_write);
  const auto t_check = std::chrono::steady_clock::now();

  // Self-check: the file as any other command will read it.
  try {
    const LedMap back = LedMap::load(a.out);
    check_frequency_reuse(back, camera, a.device_height_m, a.out);
    if (back.size() != layout.leds.size())
      throw std::runtime_error("holds " + std::to_string(back.size()) + " LEDs, not " + std::to_string(n));
    if (static_cast<int>(back.classes().size()) != static_cast<int>(std::count_if(
                                                       members.begin(), members.end(), [](int m) { return m > 0; })))
      throw std::runtime_error("re-read with " + std::to_string(back.classes().size()) + " frequency classes");
    if (back.reuses_frequencies() && back.min_reuse_distance_m() + 1e-6 < conflict)
      throw std::runtime_error("two copies are " + std::to_string(back.min_reuse_distance_m()) + " m apart");
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("self-check of the written map failed (a planner bug): ") + e.what());
  }
  const double check_s = seconds_since(t_check);
  std::printf("  self-check: %s re-read, no two copies a level camera at %.2f m sees together\n", a.out.c_str(),
              a.device_height_m);
  std::printf("  planned in %.2f s (written in %.2f s, self-checked in %.2f s, %.2f s in all) -> %s\n", plan_s,
              write_s, check_s, seconds_since(t_start), a.out.c_str());
  return 0;
}

}  // namespace

void add_calib_ledmap_plan(CLI::App& ledmap, Action& action) {
  auto a = std::make_shared<PlanArgs>();
  CLI::App* plan = ledmap.add_subcommand(
      "plan", "frequencies for a floor of lights: the band the camera separates, reused so no view holds two copies");
  plan->add_option("--layout", a->layout, "light positions: CSV (x,y[,z][,id]) or a YAML LED map (ids, positions)")
      ->check(CLI::ExistingFile);
  plan->add_option("--grid", a->grid, "a grid of lights instead: X0:X1:DX,Y0:Y1:DY (inclusive, m)");
  plan->add_option("--ceiling-height", a->ceiling_z, "z of the LEDs where the layout gives none, m (required then)");
  plan->add_option("--device-height", a->device_height_m, "height of the camera above the floor, m")
      ->capture_default_str();
  plan->add_option("--camera", a->camera, "camera file (intrinsics, row_time_us, exposure_us)")
      ->required()
      ->check(CLI::ExistingFile);
  plan->add_option("--max-tilt-deg", a->max_tilt_deg, "largest tilt of the camera from looking straight up, deg")
      ->capture_default_str();
  plan->add_option("--led-diameter", a->led_diameter_m, "LED diameter, m (the band's design blob, a conflict margin)")
      ->capture_default_str();
  plan->add_option("--margin", a->margin_m, "added to the conflict distance besides the diameter, m")
      ->capture_default_str();
  plan->add_option("--classes", a->classes, "frequency classes; 0: max(needed, min(band capacity, 12))")
      ->capture_default_str();
  plan->add_option("--seed", a->seed, "random seed (same seed -> same plan)")->capture_default_str();
  plan->add_option("--out", a->out, "LED map to write")->required();
  plan->callback([a, &action] { action = [a] { return run_plan(*a); }; });
}

}  // namespace luxloc::app
