// CSV and TUM pose files: header, column order, number format, no NaN, quaternion.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "plugins/output/pose_file_sinks.hpp"
#include "plugins/output/pose_text.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::read_text;
using luxloc::test::scratch_dir;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string f;
  std::istringstream in(s);
  while (std::getline(in, f, sep)) out.push_back(f);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

// Lines of a file that ends with '\n' (a missing final newline fails the test).
std::vector<std::string> lines(const std::string& s) {
  REQUIRE(!s.empty());
  REQUIRE(s.back() == '\n');
  return split(s.substr(0, s.size() - 1), '\n');
}

PoseEstimate sample_pose() {
  PoseEstimate p;
  p.t = 1'700'000'123'456'789'012LL;  // a Unix-epoch time: 1700000123.456789012 s
  p.p_BinW = {1.234567, -2.5, 0.9};
  p.yaw = 0.5;
  p.roll = 0.01;
  p.pitch = -0.02;
  p.sigma_x = 0.05;
  p.sigma_y = 0.07;
  p.sigma_yaw = 0.0123;
  p.sigma_z = 0.04;
  p.n_eff = 812.4;
  p.leds = 3;
  p.mode = "fused";
  p.motion = "walking";
  return p;
}

}  // namespace

TEST_CASE("pose text: time printed exactly from the ns timeline", "[io]") {
  CHECK(format_time_s(1'234'567'890, 6) == "1.234568");
  CHECK(format_time_s(1'700'000'123'456'789'012LL, 6) == "1700000123.456789");
  CHECK(format_time_s(-1'500'000, 6) == "-0.001500");
  CHECK(format_time_s(-1'000'000'000, 3) == "-1.000");
  CHECK(format_time_s(0, 6) == "0.000000");
  CHECK(format_time_s(999'999'999'6LL, 6) == "10.000000");
  CHECK(format_fixed(std::nan(""), 4).empty());
  CHECK(format_fixed(INFINITY, 4).empty());
  CHECK(format_fixed(-0.00001, 4) == "0.0000");
  CHECK(format_fixed(-1.23456, 4) == "-1.2346");
}

TEST_CASE("CSV pose sink: header, column order and number format", "[io]") {
  const auto dir = scratch_dir("io_csv_sink");
  const auto path = (dir / "poses.csv").string();
  {
    CsvPoseSink sink(path);
    sink.write(sample_pose());
    PoseEstimate unknown;  // NaN sigma and n_eff: empty fields
    unknown.t = 2'000'000'000;
    unknown.p_BinW = {1, 2, 3};
    unknown.mode = "init,with comma";
    unknown.motion = "still\nnext";
    sink.write(unknown);
    sink.flush();  // readable before the sink closes
    CHECK(lines(read_text(path)).size() == 3);
  }
  const auto l = lines(read_text(path));
  REQUIRE(l.size() == 3);
  CHECK(l[0] == "t,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode,sigma_yaw,sigma_z,motion");
  const auto f = split(l[1], ',');
  REQUIRE(f.size() == 15);
  CHECK(f[0] == "1700000123.456789");
  CHECK(f[1] == "1.23457");
  CHECK(f[2] == "-2.50000");
  CHECK(f[3] == "0.90000");
  CHECK(f[4] == "0.50000");
  CHECK(f[5] == "0.05000");
  CHECK(f[6] == "0.07000");
  CHECK(f[7] == "0.01000");
  CHECK(f[8] == "-0.02000");
  CHECK(f[9] == "812.4");
  CHECK(f[10] == "3");
  CHECK(f[11] == "fused");
  CHECK(f[12] == "0.01230");
  CHECK(f[13] == "0.04000");
  CHECK(f[14] == "walking");
  const auto g = split(l[2], ',');
  REQUIRE(g.size() == 15);
  CHECK(g[0] == "2.000000");
  CHECK(g[5].empty());
  CHECK(g[6].empty());
  CHECK(g[9].empty());
  CHECK(g[11] == "init_with comma");
  CHECK(g[12].empty());
  CHECK(g[13].empty());  // z nominal, not estimated
  CHECK(g[14] == "still_next");  // a line break would split the row
  CHECK(read_text(path).find("nan") == std::string::npos);
}

TEST_CASE("CSV pose sink: an unwritable path is a runtime error (exit 1), a bad format an InputError", "[io]") {
  try {
    CsvPoseSink sink("/nonexistent-dir/x/poses.csv");
    FAIL("no error");
  } catch (const InputError&) {
    FAIL("an InputError (exit 2): an output that cannot be written is an I/O failure (exit 1)");
  } catch (const std::runtime_error&) {
  }
  CHECK_THROWS_WITH(CsvPoseSink("/nonexistent-dir/x/poses.csv"), Catch::Contains("/nonexistent-dir/x/poses.csv"));
  CHECK(parse_pose_format("csv") == PoseFileFormat::kCsv);
  CHECK(parse_pose_format("tum") == PoseFileFormat::kTum);
  CHECK_THROWS_AS(parse_pose_format("kitti"), InputError);
}

TEST_CASE("TUM pose sink: line format and quaternion of yaw/pitch/roll", "[io]") {
  const auto dir = scratch_dir("io_tum_sink");
  const auto path = (dir / "poses.tum").string();
  PoseEstimate p = sample_pose();
  {
    auto sink = make_pose_file_sink(path, PoseFileFormat::kTum);
    sink->write(p);
    PoseEstimate bad = p;
    bad.p_BinW.x() = std::nan("");
    sink->write(bad);  // not representable: dropped and counted
    CHECK(sink->drops().count("not finite") == 1);
    PoseEstimate no_attitude = p;  // no IMU: yaw, roll, pitch unknown
    no_attitude.t += 1'000'000'000;
    no_attitude.yaw = no_attitude.roll = no_attitude.pitch = std::nan("");
    sink->write(no_attitude);  // written, orientation the identity
  }
  const auto all = lines(read_text(path));
  REQUIRE(all.size() == 2);
  CHECK(all[1].substr(all[1].size() - 40) == " 0.0000000 0.0000000 0.0000000 1.0000000");
  const std::vector<std::string> l{all[0]};
  const auto f = split(l[0], ' ');
  REQUIRE(f.size() == 8);
  CHECK(f[0] == "1700000123.456789");
  CHECK(std::stod(f[1]) == Approx(1.234567).margin(1e-5));
  CHECK(std::stod(f[3]) == Approx(0.9));
  const Eigen::Quaterniond q(std::stod(f[7]), std::stod(f[4]), std::stod(f[5]), std::stod(f[6]));
  CHECK(q.norm() == Approx(1.0).margin(1e-6));
  // The quaternion rotates body axes into the world: body x = heading (yaw) when level.
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d R_expected = (Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(p.pitch, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(p.roll, Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
  CHECK((R - R_expected).norm() < 1e-6);
  // Hand-checked value: pure yaw of 90 degrees -> (0, 0, sin 45, cos 45).
  const Eigen::Quaterniond q90 = quaternion_from_ypr(std::numbers::pi / 2, 0, 0);
  CHECK(q90.z() == Approx(std::sqrt(0.5)));
  CHECK(q90.w() == Approx(std::sqrt(0.5)));
  CHECK(q90.x() == Approx(0.0).margin(1e-12));
  // qw >= 0 even for a yaw near +-pi.
  CHECK(quaternion_from_ypr(3.1, 0, 0).w() >= 0.0);
  CHECK(quaternion_from_ypr(-3.1, 0, 0).w() >= 0.0);
}

TEST_CASE("pose files written by the sinks read back in luxloc eval", "[io]") {
  const auto dir = scratch_dir("io_sink_roundtrip");
  std::vector<PoseEstimate> poses;
  for (int i = 0; i < 20; ++i) {
    PoseEstimate p;
    p.t = 5 * kNsPerSecond + i * 33'333'333LL;
    p.p_BinW = {0.3 * i, 1.0 - 0.1 * i, 1.0};
    p.yaw = -3.0 + 0.3 * i;  // crosses +-pi on the way
    p.roll = 0.02;
    poses.push_back(p);
  }
  for (PoseFileFormat f : {PoseFileFormat::kCsv, PoseFileFormat::kTum}) {
    const auto path = (dir / (f == PoseFileFormat::kCsv ? "p.csv" : "p.tum")).string();
    {
      auto sink = make_pose_file_sink(path, f);
      for (const auto& p : poses) sink->write(p);
    }
    const auto back = read_pose_file(path);
    REQUIRE(back.size() == poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
      CHECK(std::abs(back[i].t - poses[i].t) <= 500);  // microsecond printing
      CHECK((back[i].p_inW - poses[i].p_BinW).norm() < 1e-4);
      CHECK(std::abs(std::remainder(back[i].yaw - poses[i].yaw, 2 * std::numbers::pi)) < 1e-4);
    }
  }
}
