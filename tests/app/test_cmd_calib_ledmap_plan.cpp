// `luxloc calib ledmap plan` (issue 14): a 60 m x 30 m floor of lights on a 2.5 m grid gets
// 12 frequency classes; the written map loads, passes the reuse check and, sampled from many
// poses through the camera model alone, never shows two LEDs of one class in one image.
// CSV and YAML layouts keep their ids; bad input exits 2 naming the file, line and field.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <regex>
#include <unistd.h>

#include "core/sim/scenario.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_visibility.hpp"
#include "co_visibility_check.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace luxloc::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::filesystem::path plan_dir(const std::string& name) {
  return scratch_dir("ledmap_plan_" + name + "_" + std::to_string(::getpid()));
}

// The simulator's camera (640 x 480, f 460 px, 30 us rows, 100 us exposure) as camera.yaml.
std::string write_camera(const std::filesystem::path& dir, double exposure_s = 100e-6) {
  CameraModel cam = sim::default_sim_camera();
  cam.exposure_s = exposure_s;
  const auto p = dir / "camera.yaml";
  cam.save(p.string());
  return p.string();
}

double printed(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return std::nan("");
  return std::stod(m[1].str());
}

}  // namespace

TEST_CASE("calib ledmap plan: a 60 m x 30 m floor (2.5 m grid) in 12 classes, no view holds two copies",
          "[calib][vlc][plan]") {
  const auto dir = plan_dir("floor");
  const std::string cam = write_camera(dir);
  const auto out = dir / "floor.yaml";
  const auto r = run_luxloc("calib ledmap plan --grid 1.25:58.75:2.5,1.25:28.75:2.5 --ceiling-height 3.0 --camera '" +
                            cam + "' --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(printed(r.output, R"(calib ledmap plan: (\d+) LEDs)") == 288);
  CHECK(printed(r.output, R"(classes: \d+ needed \(DSatur\), (\d+) used)") == 12);
  CHECK(printed(r.output, R"(classes: (\d+) needed)") <= 5);  // the king's graph of the grid: 4
  const double reuse = printed(r.output, R"(min reuse distance: ([0-9.]+) m)");
  const double conflict = printed(r.output, R"(conflict distance: ([0-9.]+) m)");
  CHECK(reuse >= conflict);
  CHECK(reuse >= 6.5);  // a perfect 12-class lattice on 2.5 m would reach 9.3 m
  CHECK(printed(r.output, R"(alias fraction: ([0-9.]+))") <= 0.3);
  CHECK(std::isfinite(printed(r.output, R"(planned in ([0-9.]+) s)")));

  const LedMap map = LedMap::load(out.string());
  REQUIRE(map.size() == 288);
  CHECK(map.classes().size() == 12);
  CHECK(map.reuses_frequencies());
  CHECK(map.min_reuse_distance_m() == Approx(reuse).margin(0.01));
  CHECK(map.min_relative_separation() >= 0.02);
  for (std::size_t i = 0; i < map.size(); ++i) {
    CHECK(map.leds()[i].id == static_cast<int>(i) + 1);
    CHECK(map.leds()[i].diameter_m == 0.2);
    CHECK(map.leds()[i].p_inW.z() == 3.0);
  }
  const CameraModel camera = CameraModel::load(cam);
  CHECK_NOTHROW(check_frequency_reuse(map, camera, 1.0, out.string()));
  CHECK(test::views_with_two_of_a_class(map, camera, 1.0, 15.0 * kPi / 180.0, 20000, 11) == 0);

  // Same seed, same map; the sampling check does catch a bad map (every LED one class).
  const auto out2 = dir / "again.yaml";
  REQUIRE(run_luxloc("calib ledmap plan --grid 1.25:58.75:2.5,1.25:28.75:2.5 --ceiling-height 3.0 --camera '" + cam +
                     "' --out '" + out2.string() + "'")
              .exit_code == 0);
  CHECK(read_text(out2) == read_text(out));
  std::vector<Led> one = map.leds();
  for (Led& l : one) l.freq_hz = 3000.0;
  CHECK(test::views_with_two_of_a_class(LedMap(one, "one"), camera, 1.0, 15.0 * kPi / 180.0, 200, 11) > 15);  // 33 of 200: two lights of the grid in one image
}

TEST_CASE("calib ledmap plan: an irregular office (jittered rooms, a dense corridor) is valid from every sampled pose",
          "[calib][vlc][plan]") {
  const auto dir = plan_dir("office");
  const std::string cam = write_camera(dir);
  // 60 m x 30 m: rooms lit on a 2.5 m grid with up to 0.4 m of placement error, a corridor
  // along y = 15 m lit every 1.5 m (denser than the rooms), ceilings 2.9-3.1 m.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4), dz(-0.1, 0.1);
  std::string csv = "x,y,z\n";
  int n = 0;
  const auto add = [&](double x, double y) {
    csv += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(3.0 + dz(rng)) + "\n";
    ++n;
  };
  for (int iy = 0; iy < 12; ++iy)
    for (int ix = 0; ix < 24; ++ix) {
      const double y = 1.25 + 2.5 * iy;
      if (std::abs(y - 15.0) < 1.5) continue;  // the corridor's band
      add(1.25 + 2.5 * ix + jitter(rng), y + jitter(rng));
    }
  for (double x = 0.75; x < 60.0; x += 1.5) add(x, 15.0);
  write_text(dir / "office.csv", csv);
  const auto out = dir / "office.yaml";
  const auto r = run_luxloc("calib ledmap plan --layout '" + (dir / "office.csv").string() + "' --camera '" + cam +
                            "' --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(printed(r.output, R"(classes: \d+ needed \(DSatur\), (\d+) used)") == 12);
  const LedMap map = LedMap::load(out.string());
  REQUIRE(static_cast<int>(map.size()) == n);
  CHECK(map.min_reuse_distance_m() >= printed(r.output, R"(conflict distance: ([0-9.]+) m)") - 0.01);
  const CameraModel camera = CameraModel::load(cam);
  CHECK_NOTHROW(check_frequency_reuse(map, camera, 1.0, out.string()));
  CHECK(test::views_with_two_of_a_class(map, camera, 1.0, 15.0 * kPi / 180.0, 20000, 13) == 0);
}

TEST_CASE("calib ledmap plan: CSV and YAML layouts keep their ids and heights", "[calib][vlc][plan]") {
  const auto dir = plan_dir("layouts");
  const std::string cam = write_camera(dir);
  // A corridor of 20 lights every 2 m with ids of its own, at two ceiling heights.
  std::string csv = "# corridor B\nid,x,y,z\n";
  for (int i = 0; i < 20; ++i)
    csv += std::to_string(100 + 3 * i) + "," + std::to_string(1.0 + 2.0 * i) + ",1.5," + (i < 10 ? "3.0" : "2.8") + "\n";
  write_text(dir / "corridor.csv", csv);
  const auto from_csv = dir / "from_csv.yaml";
  const auto r = run_luxloc("calib ledmap plan --layout '" + (dir / "corridor.csv").string() + "' --camera '" + cam +
                            "' --device-height 1.2 --out '" + from_csv.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const LedMap a = LedMap::load(from_csv.string());
  REQUIRE(a.size() == 20);
  for (int i = 0; i < 20; ++i) {
    CHECK(a.leds()[static_cast<std::size_t>(i)].id == 100 + 3 * i);
    CHECK(a.leds()[static_cast<std::size_t>(i)].p_inW.z() == (i < 10 ? 3.0 : 2.8));
  }
  CHECK(a.reuses_frequencies());
  CHECK_NOTHROW(check_frequency_reuse(a, CameraModel::load(cam), 1.2, "a"));

  // A YAML map with one frequency everywhere (and one missing): ids and light fields kept,
  // the frequencies replaced by a plan.
  std::string yaml = "%YAML:1.0\n---\nleds:\n";
  for (int i = 0; i < 30; ++i)
    yaml += "   - { id: " + std::to_string(500 - i) + (i == 4 ? "" : ", freq_hz: 2500.") + ", x: " +
            std::to_string(2.5 * (i % 6)) + ", y: " + std::to_string(2.5 * (i / 6)) + ", z: 3.0" +
            (i == 0 ? ", power: 1.5" : "") + " }\n";
  write_text(dir / "old.yaml", yaml);
  const auto from_yaml = dir / "from_yaml.yaml";
  const auto ry = run_luxloc("calib ledmap plan --layout '" + (dir / "old.yaml").string() + "' --camera '" + cam +
                             "' --classes 8 --seed 3 --out '" + from_yaml.string() + "'");
  INFO(ry.output);
  REQUIRE(ry.exit_code == 0);
  CHECK(printed(ry.output, R"(classes: \d+ needed \(DSatur\), (\d+) used)") == 8);
  const LedMap b = LedMap::load(from_yaml.string());
  REQUIRE(b.size() == 30);
  for (int i = 0; i < 30; ++i) CHECK(b.leds()[static_cast<std::size_t>(i)].id == 500 - i);
  CHECK(b.leds()[0].power == 1.5);
  CHECK(b.classes().size() == 8);
  CHECK_NOTHROW(check_frequency_reuse(b, CameraModel::load(cam), 1.0, "b"));
  CHECK(test::views_with_two_of_a_class(b, CameraModel::load(cam), 1.0, 15.0 * kPi / 180.0, 5000, 5) == 0);
}

TEST_CASE("calib ledmap plan: bad layouts and options exit 2 naming the file, line and field", "[calib][vlc][plan]") {
  const auto dir = plan_dir("errors");
  const std::string cam = write_camera(dir);
  const std::string out = " --out '" + (dir / "out.yaml").string() + "'";
  const auto plan = [&](const std::string& args) {
    const auto r = run_luxloc("calib ledmap plan " + args);
    UNSCOPED_INFO(args << "\n" << r.output);
    return r;
  };
  write_text(dir / "bad.csv", "x,y\n1,1\n2,x1\n3,1\n");
  auto r = plan("--layout '" + (dir / "bad.csv").string() + "' --ceiling-height 3 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("bad.csv:3: field 'y'") != std::string::npos);

  write_text(dir / "nohdr.csv", "1,1\n2,1\n");
  r = plan("--layout '" + (dir / "nohdr.csv").string() + "' --ceiling-height 3 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("nohdr.csv:1: field 'x'") != std::string::npos);
  CHECK(r.output.find("no header row") != std::string::npos);

  write_text(dir / "xy.csv", "x,y\n1,1\n4,1\n");
  r = plan("--layout '" + (dir / "xy.csv").string() + "' --camera '" + cam + "'" + out);  // no z, no ceiling
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("xy.csv:2: field 'z'") != std::string::npos);

  r = plan("--grid 0:10:2.5,0:10:2.5 --ceiling-height 3" + out);  // no --camera
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--camera") != std::string::npos);

  r = plan("--grid 0:10:2.5,0:10:2.5 --ceiling-height 0.8 --camera '" + cam + "'" + out);  // below the device
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("field '--ceiling-height'") != std::string::npos);
  CHECK(r.output.find("not above the device") != std::string::npos);
  write_text(dir / "low.csv", "x,y,z\n1,1,1.5\n4,1,1.5\n");
  r = plan("--layout '" + (dir / "low.csv").string() + "' --device-height 1.6 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("low.csv: field 'z'") != std::string::npos);

  r = plan("--grid 0:10:2.5:1,0:10:2.5 --ceiling-height 3 --camera '" + cam + "'" + out);  // bad grid spec
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--grid: field '--grid'") != std::string::npos);
  r = plan("--grid 0:10:0,0:10:2.5 --ceiling-height 3 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("step must be > 0") != std::string::npos);

  write_text(dir / "wide.csv", "x,y\n0,0\n200000,200000\n");  // 200 km apart: not one floor
  r = plan("--layout '" + (dir / "wide.csv").string() + "' --ceiling-height 3 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("wide.csv: field 'x/y': the layout spans 200000 m x 200000 m") != std::string::npos);

  r = plan("--camera '" + cam + "'" + out);  // neither a layout nor a grid
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("exactly one of --layout") != std::string::npos);
  r = plan("--layout '" + (dir / "xy.csv").string() + "' --grid 0:10:2.5,0:10:2.5 --ceiling-height 3 --camera '" + cam +
           "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("exactly one of --layout") != std::string::npos);

  // A camera file without the timing the band depends on.
  write_text(dir / "notiming.yaml",
             "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n   rows: 3\n"
             "   cols: 3\n   dt: d\n   data: [ 460., 0., 320., 0., 460., 240., 0., 0., 1. ]\n");
  r = plan("--grid 0:10:2.5,0:10:2.5 --ceiling-height 3 --camera '" + (dir / "notiming.yaml").string() + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("notiming.yaml: field 'row_time_us'") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out.yaml"));
}

TEST_CASE("calib ledmap plan: too few classes, or a band too narrow, exit 2 saying what would help",
          "[calib][vlc][plan]") {
  const auto dir = plan_dir("classes");
  const std::string cam = write_camera(dir);
  const std::string out = " --out '" + (dir / "out.yaml").string() + "'";
  const std::string floor = "--grid 1.25:58.75:2.5,1.25:28.75:2.5 --ceiling-height 3 ";
  // The 2.5 m grid needs 4 classes (the king's graph): 2 are too few.
  auto r = run_luxloc("calib ledmap plan " + floor + "--classes 2 --camera '" + cam + "'" + out);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--classes: field '--classes': 2 classes are too few") != std::string::npos);
  CHECK(r.output.find("needs 4 classes") != std::string::npos);
  // More classes than the band holds.
  r = run_luxloc("calib ledmap plan " + floor + "--classes 200 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("field 'exposure_us': --classes 200 asks for more classes than fit") != std::string::npos);
  // A 2 ms exposure averages the stripes away above ~300 Hz, below the lowest frequency a
  // far blob still shows two periods of: no band at all.
  const auto slow_dir = dir / "slow";
  std::filesystem::create_directories(slow_dir);
  const std::string slow = write_camera(slow_dir, 2e-3);
  r = run_luxloc("calib ledmap plan " + floor + "--camera '" + slow + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("slow/camera.yaml: field 'exposure_us'") != std::string::npos);
  CHECK(r.output.find("a shorter exposure (now 2000 us)") != std::string::npos);
  // LEDs so dense (0.5 m) that more classes are needed than a 230 us exposure's band holds
  // (2.3 - 2.6 kHz: 5 classes).
  const auto mid_dir = dir / "mid";
  std::filesystem::create_directories(mid_dir);
  const std::string mid = write_camera(mid_dir, 230e-6);
  r = run_luxloc("calib ledmap plan --grid 0:6:0.5,0:6:0.5 --ceiling-height 3 --camera '" + mid + "'" + out);
  CHECK(r.output.find("5 classes fit") != std::string::npos);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("mid/camera.yaml: field 'exposure_us': Too many LEDs close together: the layout needs at least") != std::string::npos);
  CHECK(r.output.find("LEDs farther apart") != std::string::npos);
  // A 2 m grid passes that bound (5 LEDs within 2.29 m of one) but DSatur needs more than 5.
  r = run_luxloc("calib ledmap plan --grid 0:20:2,0:20:2 --ceiling-height 3 --camera '" + mid + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(std::regex_search(r.output, std::regex("mid/camera.yaml: field 'exposure_us': Too many LEDs close together: "
                                               "the layout needs ([6-9]|1[0-9]) classes \\(LEDs closer than 4.58 m")));
  // A 1 m grid under the 100 us camera: 21 LEDs within 2.29 m of one, so --classes 12 is
  // refused before any colouring (the band holds 33).
  r = run_luxloc("calib ledmap plan --grid 0:10:1,0:10:1 --ceiling-height 3 --classes 12 --camera '" + cam + "'" + out);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--classes: field '--classes': 12 classes are too few: the layout needs at least 21 classes") !=
        std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out.yaml"));
}
