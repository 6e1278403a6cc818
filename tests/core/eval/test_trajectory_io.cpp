// Reading ground truth and pose files for evaluation (CSV by column name, TUM detected).
#include <catch2/catch.hpp>
#include <cmath>

#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::scratch_dir;
using luxloc::test::shared_dir;
using luxloc::test::write_text;

TEST_CASE("eval io: the fixture's ground truth reads as is", "[io]") {
  const auto rows = read_truth_csv((shared_dir() / "fixtures" / "spec-sample" / "groundtruth.csv").string());
  REQUIRE(rows.size() == 1201);
  CHECK(rows.front().t == 0);
  CHECK(rows.back().t == 12 * kNsPerSecond);
  CHECK(rows.front().p_inW.x() == Approx(1.15230));
  CHECK(rows.front().yaw == Approx(1.65444));
}

TEST_CASE("eval io: pose CSV by column name, TUM detected", "[io]") {
  const auto dir = scratch_dir("io_eval_io");
  write_text(dir / "poses.csv", "t,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode\n"
                                "1.000000,1.0,2.0,0.9,0.5,,,0,0,,2,fused\n"
                                "0.500000,1.5,2.5,0.9,,0.1,0.1,0,0,10.0,0,init\n");
  auto p = read_pose_file((dir / "poses.csv").string());
  REQUIRE(p.size() == 2);
  CHECK(p[0].t == kNsPerSecond);
  CHECK(p[0].yaw == Approx(0.5));
  CHECK(std::isnan(p[1].yaw));
  CHECK(p[1].p_inW.y() == Approx(2.5));

  write_text(dir / "yx.csv", "y,t,x\n2.0,1.0,3.0\n");  // order free, no z / yaw
  p = read_pose_file((dir / "yx.csv").string());
  REQUIRE(p.size() == 1);
  CHECK(p[0].p_inW.x() == Approx(3.0));
  CHECK(std::isnan(p[0].yaw));

  // TUM: yaw 90 degrees = quaternion (0, 0, sin 45, cos 45).
  write_text(dir / "poses.tum", "# timestamp tx ty tz qx qy qz qw\n"
                                "1.0 1.0 2.0 0.9 0 0 0.7071068 0.7071068\n"
                                "1.1\t1.1 2.0 0.9 0 0 0 1\n");
  p = read_pose_file((dir / "poses.tum").string());
  REQUIRE(p.size() == 2);
  CHECK(p[0].yaw == Approx(M_PI / 2));
  CHECK(p[1].yaw == Approx(0.0).margin(1e-12));
  CHECK(p[1].t == seconds_to_ns(1.1));
}

TEST_CASE("eval io: bad input names file, line and field", "[io]") {
  const auto dir = scratch_dir("io_eval_io_bad");
  auto expect = [&](const std::string& name, const std::string& text, int line, const std::string& field,
                    bool truth = false) {
    write_text(dir / name, text);
    try {
      if (truth)
        read_truth_csv((dir / name).string());
      else
        read_pose_file((dir / name).string());
      FAIL("no InputError for " << name);
    } catch (const InputError& e) {
      CHECK_THAT(e.file(), Catch::Contains(name));
      CHECK(e.line() == line);
      CHECK(e.field() == field);
    }
  };
  expect("empty.csv", "", 0, "");
  expect("header_only.csv", "t,x,y,z,yaw\n", 0, "");
  expect("bad_x.csv", "t,x,y\n0,0,0\n1,oops,0\n", 3, "x");
  expect("no_y.csv", "t,x\n0,0\n", 1, "y");
  expect("short_tum.txt", "1.0 1 2 3 0 0 0\n", 1, "qw");
  expect("bad_tum.txt", "1.0 1 2 3 0 0 0 1\n2.0 1 z 3 0 0 0 1\n", 2, "ty");
  expect("truth_dup.csv", "t,x,y\n0,0,0\n1,1,1\n1,1,1\n", 4, "t", true);
  expect("truth_back.csv", "t,x,y\n0,0,0\n1,1,1\n0.5,1,1\n", 4, "t", true);
  expect("truth_one.csv", "t,x,y\n0,0,0\n", 0, "", true);
  CHECK_THROWS_WITH(read_pose_file((dir / "header_only.csv").string()), Catch::Contains("no poses"));
  CHECK_THROWS_WITH(read_pose_file((dir / "empty.csv").string()), Catch::Contains("no poses"));
}
