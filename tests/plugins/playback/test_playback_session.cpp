// Session-folder playback: the fixture reads as is; bad rows, missing frames and broken
// side files follow the bad-input policy (skip + count, or InputError naming file/field).
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/common/input_error.hpp"
#include "plugins/playback/csv_row_source.hpp"
#include "plugins/playback/frame_list_source.hpp"
#include "plugins/playback/imu_csv_source.hpp"
#include "plugins/playback/playback_session.hpp"
#include "core/common/session_file.hpp"
#include "plugins/playback/uwb_csv_source.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::scratch_dir;
using luxloc::test::shared_dir;
using luxloc::test::write_text;
namespace fs = std::filesystem;

namespace {

std::vector<SensorData> drain(Source& s) {
  std::vector<SensorData> out;
  SensorData d;
  while (s.next(d)) out.push_back(d);
  return out;
}

Source* find_source(PlaybackSession& s, const std::string& name) {
  for (auto& src : s.sources)
    if (src->name() == name) return src.get();
  return nullptr;
}

std::string first_message(const Source& s, const std::string& reason) {
  const auto snap = s.drops().snapshot();
  auto it = snap.find(reason);
  return it == snap.end() ? std::string() : it->second.first_message;
}

const char* kGoodMap =
    "%YAML:1.0\n---\nleds:\n"
    "   - { id: 1, freq_hz: 1500.0, x: 1.0, y: 1.0, z: 3.0 }\n"
    "   - { id: 2, freq_hz: 2300.0, x: 3.0, y: 1.0, z: 3.0 }\n";

}  // namespace

TEST_CASE("playback: the spec-sample fixture reads as is", "[io]") {
  const fs::path dir = shared_dir() / "fixtures" / "spec-sample";
  PlaybackSession s = open_playback(dir);
  CHECK(s.config.device_height_m == Approx(1.0));
  REQUIRE(s.map);
  CHECK(s.map->size() == 9);
  REQUIRE(s.map->find_id(5));
  CHECK(s.map->find_id(5)->freq_hz == Approx(3900.0));
  REQUIRE(s.camera);
  CHECK(s.camera->width == 640);
  CHECK(s.camera->height == 480);
  CHECK(s.camera->fx == Approx(460.0));
  CHECK(s.camera->row_time_s == Approx(26e-6));
  REQUIRE(s.groundtruth);
  CHECK(s.groundtruth->filename() == "groundtruth.csv");
  REQUIRE(s.sources.size() == 2);  // imu + frames; no uwb/fixes/odom in the fixture

  Source* imu = find_source(s, "playback:imu");
  REQUIRE(imu);
  const auto rows = drain(*imu);
  REQUIRE(rows.size() == 1201);
  const auto& first = std::get<ImuSample>(rows.front());
  const auto& last = std::get<ImuSample>(rows.back());
  CHECK(first.t == 0);
  CHECK(last.t == 12 * kNsPerSecond);
  CHECK(first.acc_inB.z() == Approx(9.776024));
  CHECK(first.gyro_inB.y() == Approx(0.005180));
  CHECK(first.has_mag);
  CHECK(first.mag_inB.x() == Approx(21.864));
  CHECK(imu->drops().total() == 0);

  Source* frames = find_source(s, "playback:frames");
  REQUIRE(frames);
  const auto imgs = drain(*frames);
  REQUIRE(imgs.size() == 359);
  const auto& f0 = std::get<FrameSample>(imgs.front());
  CHECK(f0.t == seconds_to_ns(0.0123));
  CHECK(std::get<FrameSample>(imgs.back()).t == seconds_to_ns(11.945633));
  CHECK(f0.gray.type() == CV_8UC1);
  CHECK(f0.gray.cols == 640);
  CHECK(f0.gray.rows == 480);
  CHECK(frames->drops().total() == 0);
}

TEST_CASE("playback: a garbage IMU row is skipped and counted, every good row still comes out", "[io]") {
  const fs::path dir = scratch_dir("io_playback_garbage");
  write_text(dir / "imu.csv",
             "# a comment\n"
             "t,ax,ay,az,gx,gy,gz\n"
             "0.1,0,0,9.81,0,0,0\n"
             "0.2,0,0,9.81,0,0,0.1\n"
             "0.25,abc,1,2,3,4,5\n"
             "0.3,0,0,9.81,0,0,0.2\n"
             "0.35,0,0,9.81\n"        // too few fields
             "0.36,0,0,nan,0,0,0\n"   // not finite
             "\n"
             "0.4,0,0,9.81,0,0,0.3\n"
             "0.5,0,0,9.81,0,0,0.4\n");
  PlaybackSession s = open_playback(dir);
  REQUIRE(s.sources.size() == 1);
  CHECK_FALSE(s.map);
  CHECK_FALSE(s.camera);
  const auto rows = drain(*s.sources[0]);
  REQUIRE(rows.size() == 5);
  std::vector<double> gz;
  for (const auto& r : rows) gz.push_back(std::get<ImuSample>(r).gyro_inB.z());
  CHECK(gz == std::vector<double>{0.0, 0.1, 0.2, 0.3, 0.4});
  CHECK_FALSE(std::get<ImuSample>(rows[0]).has_mag);
  CHECK(s.sources[0]->drops().count(playback_drop::kBadRow) == 3);
  const std::string msg = first_message(*s.sources[0], playback_drop::kBadRow);
  CHECK_THAT(msg, Catch::Contains("imu.csv:5: field 'ax': not a number: 'abc'"));
}

TEST_CASE("playback: out-of-order and duplicated rows are skipped and counted", "[io]") {
  const fs::path dir = scratch_dir("io_playback_order");
  write_text(dir / "imu.csv",
             "t,gx,gy,gz,ax,ay,az\n"  // columns by name, any order
             "1.0,0.1,0,0,0,0,9.8\n"
             "1.1,0.2,0,0,0,0,9.8\n"
             "1.05,0.9,0,0,0,0,9.8\n"  // backwards
             "1.1,0.9,0,0,0,0,9.8\n"   // duplicate
             "1.2,0.3,0,0,0,0,9.8\n");
  PlaybackSession s = open_playback(dir);
  const auto rows = drain(*s.sources[0]);
  REQUIRE(rows.size() == 3);
  CHECK(std::get<ImuSample>(rows[2]).gyro_inB.x() == Approx(0.3));
  CHECK(std::get<ImuSample>(rows[2]).acc_inB.z() == Approx(9.8));
  CHECK(s.sources[0]->drops().count(playback_drop::kOutOfOrder) == 1);
  CHECK(s.sources[0]->drops().count(playback_drop::kDuplicateTime) == 1);
  CHECK_THAT(first_message(*s.sources[0], playback_drop::kOutOfOrder), Catch::Contains("imu.csv:4: field 't'"));
}

TEST_CASE("playback: UWB rows of several anchors may share a time stamp, aoa optional", "[io]") {
  const fs::path dir = scratch_dir("io_playback_uwb");
  write_text(dir / "uwb.csv",
             "t,anchor,range_m,aoa_rad\n"
             "1.0,1,2.5,0.3\n"
             "1.0,2,3.5,\n"
             "1.0,2,3.6,\n"   // same (t, anchor): duplicate
             "1.1,1.5,2.0,\n"  // anchor not an integer
             "1.2,1,-0.5,\n"   // negative range
             "1.3,1,2.4,0.2\n");
  PlaybackSession s = open_playback(dir);
  REQUIRE(s.sources.size() == 1);
  const auto rows = drain(*s.sources[0]);
  REQUIRE(rows.size() == 3);
  CHECK(s.sources[0]->drops().count(playback_drop::kOutOfRange) == 1);  // the negative range
  CHECK_THAT(first_message(*s.sources[0], playback_drop::kOutOfRange), Catch::Contains("uwb.csv:6: field 'range_m'"));
  const auto& a = std::get<UwbSample>(rows[0]);
  const auto& b = std::get<UwbSample>(rows[1]);
  CHECK(a.anchor == 1);
  CHECK(a.aoa_rad == Approx(0.3));
  CHECK(b.anchor == 2);
  CHECK(b.range_m == Approx(3.5));
  CHECK(std::isnan(b.aoa_rad));
  CHECK(s.sources[0]->drops().count(playback_drop::kDuplicateTime) == 1);
  CHECK(s.sources[0]->drops().count(playback_drop::kBadRow) == 1);
}

TEST_CASE("playback: fixes and odometry stream with their optional columns", "[io]") {
  const fs::path dir = scratch_dir("io_playback_fix_odom");
  write_text(dir / "fixes.csv", "t,x,y,sigma_m\n0.5,1.0,2.0,0.3\n0.6,1.1,2.1,\n0.7,1,2,0\n");
  write_text(dir / "odom.csv", "t,dist_m,dyaw_rad,extra\n0.5,0.1,0.01,foo\n0.6,0.2,-0.02,bar\n");
  PlaybackSession s = open_playback(dir);
  REQUIRE(s.sources.size() == 2);
  const auto fixes = drain(*s.sources[0]);
  REQUIRE(fixes.size() == 2);
  CHECK(std::get<FixSample>(fixes[0]).sigma_m == Approx(0.3));
  CHECK(std::get<FixSample>(fixes[0]).p_inW.y() == Approx(2.0));
  CHECK(std::isnan(std::get<FixSample>(fixes[1]).sigma_m));
  CHECK(s.sources[0]->drops().count(playback_drop::kBadRow) == 1);  // sigma_m = 0
  const auto odom = drain(*s.sources[1]);
  REQUIRE(odom.size() == 2);
  CHECK(std::get<OdomSample>(odom[1]).dist_m == Approx(0.2));
  CHECK(std::get<OdomSample>(odom[1]).dyaw_rad == Approx(-0.02));
}

TEST_CASE("playback: a missing frame or a frame of the wrong size is skipped and counted", "[io]") {
  const fs::path dir = scratch_dir("io_playback_frames");
  fs::create_directories(dir / "frames");
  cv::Mat gray(48, 64, CV_8UC1, cv::Scalar(77));
  cv::Mat colour(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  REQUIRE(cv::imwrite((dir / "frames" / "000000.png").string(), gray));
  REQUIRE(cv::imwrite((dir / "frames" / "000002.jpg").string(), colour));
  REQUIRE(cv::imwrite((dir / "frames" / "000003.png").string(), cv::Mat(40, 64, CV_8UC1, cv::Scalar(1))));
  write_text(dir / "frames" / "000004.png", "not a png");
  REQUIRE(cv::imwrite((dir / "frames" / "000005.png").string(), gray));
  write_text(dir / "frames.csv",
             "t,file\n"
             "0.00,frames/000000.png\n"
             "0.03,frames/000001.png\n"  // missing
             "0.06,frames/000002.jpg\n"  // colour JPG -> gray
             "0.09,frames/000003.png\n"  // 64x40, camera says 64x48
             "0.12,frames/000004.png\n"  // unreadable
             "0.15,frames/000005.png\n");
  FrameListSource src((dir / "frames.csv").string(), dir, cv::Size(64, 48));
  const auto out = drain(src);
  REQUIRE(out.size() == 3);
  const auto& jpg = std::get<FrameSample>(out[1]);
  CHECK(jpg.t == seconds_to_ns(0.06));
  CHECK(jpg.gray.type() == CV_8UC1);
  CHECK(cv::mean(jpg.gray)[0] > 90.0);  // green-dominated colour converted to a mid gray
  CHECK(std::get<FrameSample>(out[2]).t == seconds_to_ns(0.15));
  CHECK(src.drops().count(playback_drop::kMissingFrame) == 1);
  CHECK(src.drops().count(playback_drop::kBadFrame) == 1);
  CHECK_THAT(first_message(src, playback_drop::kBadFrame),
             Catch::Contains("frames.csv:6: field 'file': cannot read 'frames/000004.png': not a PNG or JPEG file"));
  CHECK(src.drops().count(playback_drop::kFrameSize) == 1);
  CHECK_THAT(first_message(src, playback_drop::kMissingFrame),
             Catch::Contains("frames.csv:3: field 'file': cannot read 'frames/000001.png'"));
  CHECK_THAT(first_message(src, playback_drop::kFrameSize), Catch::Contains("64x40"));
}

TEST_CASE("playback: broken LED maps are rejected naming the file and the field", "[io]") {
  const fs::path dir = scratch_dir("io_playback_badmap");
  write_text(dir / "imu.csv", "t,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
  auto expect_error = [&](const std::string& map, const std::string& field, const std::string& text) {
    write_text(dir / "ledmap.yaml", map);
    try {
      open_playback(dir);
      FAIL("no InputError for map:\n" << map);
    } catch (const InputError& e) {
      CHECK_THAT(e.file(), Catch::Contains("ledmap.yaml"));
      CHECK(e.field() == field);
      CHECK_THAT(std::string(e.what()), Catch::Contains(text));
    }
  };
  expect_error("%YAML:1.0\n---\nleds:\n   - { id: 1, freq_hz: 1500.0, x: 1.0, y: [1.0, z: 3.0 }\n", "", "YAML");
  expect_error("%YAML:1.0\n---\nleds:\n   - { id: 1, x: 1.0, y: 1.0, z: 3.0 }\n", "freq_hz", "LED #1");
  expect_error(
      "%YAML:1.0\n---\nleds:\n   - { id: 4, freq_hz: 1500.0, x: 1.0, y: 1.0, z: 3.0 }\n"
      "   - { id: 4, freq_hz: 2500.0, x: 2.0, y: 1.0, z: 3.0 }\n",
      "id", "id 4");
  write_text(dir / "ledmap.yaml", kGoodMap);
  CHECK(open_playback(dir).map->size() == 2);
}

TEST_CASE("playback: unusable session folders are InputErrors", "[io]") {
  const fs::path dir = scratch_dir("io_playback_errors");
  SECTION("missing folder") { CHECK_THROWS_AS(open_playback(dir / "nope"), InputError); }
  SECTION("no sensor file at all") {
    write_text(dir / "ledmap.yaml", kGoodMap);
    write_text(dir / "groundtruth.csv", "t,x,y\n0,0,0\n1,1,1\n");
    CHECK_THROWS_WITH(open_playback(dir), Catch::Contains("no sensor file"));
  }
  SECTION("a required column is missing") {
    write_text(dir / "imu.csv", "t,ax,ay,az,gx,gy\n0,0,0,9.8,0,0\n");
    try {
      open_playback(dir);
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.field() == "gz");
      CHECK(e.line() == 1);
      CHECK_THAT(e.file(), Catch::Contains("imu.csv"));
    }
  }
  SECTION("a broken camera file") {
    write_text(dir / "imu.csv", "t,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
    write_text(dir / "camera.yaml", "%YAML:1.0\n---\nimage_width: 640\n");
    try {
      open_playback(dir);
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.file(), Catch::Contains("camera.yaml"));
      CHECK(e.field() == "image_height");
    }
  }
  SECTION("a broken session.yaml") {
    write_text(dir / "imu.csv", "t,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
    write_text(dir / "session.yaml", "%YAML:1.0\n---\ndevice_height_m: high\n");
    try {
      open_playback(dir);
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK_THAT(e.file(), Catch::Contains("session.yaml"));
      CHECK(e.field() == "device_height_m");
    }
    write_text(dir / "session.yaml",
               "%YAML:1.0\n---\nanchors:\n   - { id: 1, x: 0, y: 0, z: 2 }\n   - { id: 1, x: 5, y: 0, z: 2 }\n");
    CHECK_THROWS_WITH(open_playback(dir), Catch::Contains("duplicate id 1"));
    write_text(dir / "session.yaml", "%YAML:1.0\n---\nimu: other_imu.csv\n");
    CHECK_THROWS_WITH(open_playback(dir), Catch::Contains("other_imu.csv"));
  }
  SECTION("--map naming a missing file") {
    write_text(dir / "imu.csv", "t,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
    PlaybackOptions o;
    o.map_path = dir / "absent.yaml";
    CHECK_THROWS_AS(open_playback(dir, o), InputError);
  }
}

TEST_CASE("playback: session.yaml anchors, height and file-name overrides, --map / --camera", "[io]") {
  const fs::path dir = scratch_dir("io_playback_session_yaml");
  fs::create_directories(dir / "raw");
  write_text(dir / "raw" / "ranges.csv", "t,anchor,range_m\n0.1,3,4.0\n");
  write_text(dir / "my_map.yaml", kGoodMap);
  write_text(dir / "session.yaml",
             "%YAML:1.0\n---\ndevice_height_m: 0.85\n"
             "anchors:\n   - { id: 3, x: 0.5, y: 6.0, z: 2.4 }\n   - { id: 4, x: 7, y: 0, z: 2.4 }\n"
             "uwb: raw/ranges.csv\nledmap: my_map.yaml\n");
  PlaybackSession s = open_playback(dir);
  CHECK(s.config.device_height_m == Approx(0.85));
  REQUIRE(s.config.anchors.size() == 2);
  CHECK(s.config.anchors[0].id == 3);
  CHECK(s.config.anchors[0].p_inW.y() == Approx(6.0));
  CHECK(s.config.uwb_file == "raw/ranges.csv");
  REQUIRE(s.map);
  CHECK(s.map->size() == 2);
  CHECK_FALSE(s.groundtruth);
  REQUIRE(s.sources.size() == 1);
  CHECK(drain(*s.sources[0]).size() == 1);

  // Round trip through save_session_config.
  save_session_config(s.config, (dir / "copy.yaml").string());
  const SessionConfig c = load_session_config((dir / "copy.yaml").string());
  CHECK(c.device_height_m == Approx(0.85));
  CHECK(c.anchors.size() == 2);
  CHECK(c.ledmap_file == "my_map.yaml");

  // Command-line overrides win over the session's files.
  PlaybackOptions o;
  o.map_path = shared_dir() / "fixtures" / "spec-sample" / "ledmap.yaml";
  o.camera_path = shared_dir() / "fixtures" / "spec-sample" / "camera.yaml";
  PlaybackSession t = open_playback(dir, o);
  CHECK(t.map->size() == 9);
  REQUIRE(t.camera);
  CHECK(t.camera->fx == Approx(460.0));
}
