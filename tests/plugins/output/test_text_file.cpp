// TextFile, the pose files' writer, when the disk fills up or the path is unusable: a clear
// error naming the file and the cause, and a file that holds whole lines only.
#include <catch2/catch.hpp>
#include <sstream>

#include "plugins/output/text_file.hpp"
#include "small_tmpfs.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

std::string row(int k) { return "row " + std::to_string(k) + ",0.12345,0.67890,1.00000,fused\n"; }

}  // namespace

TEST_CASE("TextFile on a full disk (64 KiB tmpfs): whole lines kept, the error names file and cause", "[io]") {
  test::SmallTmpfs fs(test::scratch_dir("textfile_full") / "mnt", "64k");
  if (!fs.available()) {
    WARN("cannot mount a tmpfs (not root): full-disk test on /dev/full only");
  } else {
    const std::string path = (fs.dir() / "poses.csv").string();
    TextFile f(path);
    int written = 0;
    std::string error;
    try {
      for (; written < 100000; ++written) f.write(row(written));
      f.flush();
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
    INFO(error);
    CHECK_THAT(error, Catch::Contains(path) && Catch::Contains("no space left on the device"));
    CHECK(f.failed());
    CHECK_THROWS_WITH(f.write(row(0)), Catch::Contains("no space left"));  // and stays failed
    const std::string text = test::read_text(path);
    REQUIRE(!text.empty());
    CHECK(text.back() == '\n');
    std::istringstream in(text);
    std::string line;
    int k = 0;
    while (std::getline(in, line)) {
      REQUIRE(line + "\n" == row(k));  // every line whole, in order, none lost before the cut
      ++k;
    }
    CHECK(static_cast<std::uint64_t>(k) == f.lines_on_disk());
    CHECK(k > 500);                // most of the 64 KiB
    CHECK_THAT(error, Catch::Contains("the " + std::to_string(k) + " complete lines written before are kept"));
  }
  TextFile full("/dev/full");
  full.write(row(0));
  CHECK_THROWS_WITH(full.flush(), Catch::Contains("/dev/full") && Catch::Contains("ENOSPC"));
}

TEST_CASE("TextFile: a path that cannot be created is a runtime error (exit 1) naming it and why", "[io]") {
  CHECK_THROWS_WITH(TextFile("/nonexistent-dir/x/poses.csv"),
                    Catch::Contains("cannot create output file '/nonexistent-dir/x/poses.csv'") &&
                        Catch::Contains("No such file"));
  test::SmallTmpfs ro(test::scratch_dir("textfile_ro") / "mnt", "16k", true);
  if (ro.available())
    CHECK_THROWS_WITH(TextFile((ro.dir() / "p.csv").string()), Catch::Contains("Read-only file system"));
}
