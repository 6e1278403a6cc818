// Durable outputs (issue 13): a closed pipe on `--out -`, a full disk under `--out`, an
// unwritable path, a full disk under `--record`. Each: a clear message, exit 1, and every
// pose already written intact; a failed recording leaves the fusion going.
#include <catch2/catch.hpp>
#include <array>
#include <cstdio>

#include "core/eval/trajectory_io.hpp"
#include "small_tmpfs.hpp"
#include "test_support.hpp"

using namespace luxloc::test;

namespace {

const std::string kDemo = std::string(LUXLOC_SOURCE_DIR) + "/data/demo-walk";

CommandResult shell(const std::string& script) { return run_command("bash -c \"" + script + "\" 2>&1"); }

std::size_t lines(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

}  // namespace

TEST_CASE("Durable outputs: run --out - piped into head: a clear message, exit 1, no death by SIGPIPE", "[app][io]") {
  const auto dir = scratch_dir("durable_sigpipe");
  const CommandResult r = shell("'" + std::string(LUXLOC_BIN) + "' run --playback '" + kDemo + "' --out - 2>'" +
                                (dir / "err.txt").string() + "' | head -n 5 >'" + (dir / "head.txt").string() +
                                "'; echo rc=\\${PIPESTATUS[0]}");
  INFO(r.output);
  CHECK_THAT(r.output, Catch::Contains("rc=1"));
  const std::string err = read_text(dir / "err.txt");
  INFO(err);
  CHECK_THAT(err, Catch::Contains("runtime failure") && Catch::Contains("cannot write stdout") &&
                      Catch::Contains("the reader closed the pipe (EPIPE)") && Catch::Contains("the run stopped"));
  CHECK_THAT(err, Catch::Contains("luxloc: stopped:"));  // the report, as after a signal
  const std::string head = read_text(dir / "head.txt");
  CHECK(lines(head) == 5);
  CHECK(head.rfind("t,x,y,z,yaw", 0) == 0);
}

TEST_CASE("Durable outputs: --out on a full disk (64 KiB tmpfs): a clear message, exit 1, every row whole", "[app][io]") {
  const auto dir = scratch_dir("durable_full");
  SmallTmpfs fs(dir / "mnt", "64k");
  if (!fs.available()) {
    WARN("cannot mount a tmpfs (not root): full-disk test skipped");
    return;
  }
  const auto poses = fs.dir() / "poses.csv";
  const CommandResult r = run_luxloc("run --playback '" + kDemo + "' --out '" + poses.string() + "'");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Catch::Contains("cannot write '" + poses.string() + "'") &&
                           Catch::Contains("no space left on the device") && Catch::Contains("the run stopped"));
  const std::string text = read_text(poses);
  REQUIRE(text.size() > 30000);
  CHECK(text.back() == '\n');  // no half row
  const auto rows = luxloc::read_pose_file(poses.string());
  CHECK(rows.size() + 1 == lines(text));  // every line parses
  CHECK_THAT(r.output, Catch::Contains("the " + std::to_string(lines(text)) + " complete lines written before are kept"));
}

TEST_CASE("Durable outputs: an --out path that cannot be created: a clear message, exit 1", "[app][io]") {
  const CommandResult r = run_luxloc("run --playback '" + kDemo + "' --out /nonexistent-dir/poses.csv");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Catch::Contains("cannot create output file '/nonexistent-dir/poses.csv'") &&
                           Catch::Contains("No such file or directory"));
}

TEST_CASE("Durable outputs: --record on a full disk stops recording with a message, the fusion goes on", "[app][io]") {
  const auto dir = scratch_dir("durable_record_full");
  SmallTmpfs fs(dir / "mnt", "600k");
  if (!fs.available()) {
    WARN("cannot mount a tmpfs (not root): full-disk recording test skipped");
    return;
  }
  const auto plain = dir / "plain.csv", with_record = dir / "recorded.csv";
  REQUIRE(run_luxloc("run --playback '" + kDemo + "' --seed 4 -q --out '" + plain.string() + "'").exit_code == 0);
  const CommandResult r = run_luxloc("run --playback '" + kDemo + "' --seed 4 --out '" + with_record.string() +
                                     "' --record '" + (fs.dir() / "rec").string() + "'");
  INFO(r.output);
  CHECK(r.exit_code == 1);  // the recording is incomplete: a runtime failure, said at the end
  CHECK_THAT(r.output, Catch::Contains("luxloc: record:") && Catch::Contains("recording stopped") &&
                           Catch::Contains("the run goes on"));
  CHECK_THAT(r.output, Catch::Contains("luxloc: done:"));  // not stopped: the whole session was fused
  // The fusion did not notice: the same poses as without --record.
  CHECK(read_text(with_record) == read_text(plain));
  // What was recorded holds whole rows only.
  for (const char* name : {"imu.csv", "frames.csv"}) {
    const auto p = fs.dir() / "rec" / name;
    if (!std::filesystem::exists(p)) continue;
    const std::string text = read_text(p);
    INFO(name);
    CHECK((text.empty() || text.back() == '\n'));
  }
}
