// Record -> playback: a live `sim:` run recorded with --record replays bit for bit; `luxloc
// record` writes a session folder that plays back.
#include <catch2/catch.hpp>

#include "core/eval/trajectory_io.hpp"
#include "test_support.hpp"

using namespace luxloc::test;

TEST_CASE("A live sim: run recorded with --record plays back to the same poses, bit for bit", "[app][io]") {
  const auto dir = scratch_dir("cmd_record_bits");
  const auto live = run_luxloc("run --source sim:walk,duration=3,seed=9 --seed 4 --out '" + (dir / "live.csv").string() +
                               "' --record '" + (dir / "rec").string() + "'");
  INFO(live.output);
  REQUIRE(live.exit_code == 0);
  const auto play = run_luxloc("run --playback '" + (dir / "rec").string() + "' --seed 4 --out '" +
                               (dir / "play.csv").string() + "'");
  INFO(play.output);
  REQUIRE(play.exit_code == 0);
  const std::string a = read_text(dir / "live.csv"), b = read_text(dir / "play.csv");
  CHECK(luxloc::read_pose_file((dir / "live.csv").string()).size() > 100);
  CHECK(a == b);
  // Another seed of the filter gives other poses: the comparison can fail.
  REQUIRE(run_luxloc("run --playback '" + (dir / "rec").string() + "' --seed 5 --out '" + (dir / "other.csv").string() +
                     "'").exit_code == 0);
  CHECK(read_text(dir / "other.csv") != a);
}

TEST_CASE("luxloc record: writes a session folder, refuses to overwrite one, needs a live source", "[app][io]") {
  const auto dir = scratch_dir("cmd_record");
  const auto rec = run_luxloc("record --source sim:square,duration=1.5 --out '" + (dir / "s").string() + "'");
  INFO(rec.output);
  REQUIRE(rec.exit_code == 0);
  CHECK(rec.output.find("wrote imu.csv: 150 rows") != std::string::npos);
  CHECK(rec.output.find("wrote frames.csv: 45 rows") != std::string::npos);
  for (const char* f : {"imu.csv", "frames.csv", "ledmap.yaml", "camera.yaml", "session.yaml", "frames/000044.png"})
    CHECK(std::filesystem::exists(dir / "s" / f));
  const auto play = run_luxloc("run --playback '" + (dir / "s").string() + "' --out '" + (dir / "p.csv").string() + "'");
  INFO(play.output);
  CHECK(play.exit_code == 0);
  const auto again = run_luxloc("record --source sim:square,duration=1 --out '" + (dir / "s").string() + "'");
  CHECK(again.exit_code == 2);
  CHECK(again.output.find("already holds a session") != std::string::npos);
  CHECK(run_luxloc("record --out '" + (dir / "t").string() + "'").exit_code == 2);
  CHECK(run_luxloc("record --source nope:x --out '" + (dir / "t").string() + "'").exit_code == 2);
}
