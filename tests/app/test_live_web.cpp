// `luxloc run --web`: a real headless browser (Debian's chromium) opens the live page of a
// `sim:` run and the DOM it ends with shows the map, the trajectory and the pose having
// updated; bad --web options stop with exit 2. A missing chromium FAILS (never skipped).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <regex>
#include <thread>
#include <unistd.h>

#include "plugins/output/mqtt_broker.hpp"  // free_tcp_port, port_accepts
#include "test_support.hpp"

using namespace luxloc::test;

namespace {

std::string chromium_binary() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (::access(p, X_OK) == 0) return p;
  FAIL("chromium is not installed (Debian package 'chromium'; scripts/setup.sh installs it)");
  return {};
}

// The text of the element with this id in a dumped DOM ("" when absent).
std::string element_text(const std::string& dom, const std::string& id) {
  std::smatch m;
  if (std::regex_search(dom, m, std::regex("id=\"" + id + "\"[^>]*>([^<]*)<"))) return m[1];
  return {};
}

double number_of(const std::string& dom, const std::string& id) {
  const std::string t = element_text(dom, id);
  INFO("#" << id << " = '" << t << "'");
  REQUIRE(!t.empty());
  return std::stod(t);
}

}  // namespace

TEST_CASE("Headless chromium watches a live sim run: map, trajectory and pose drawn and updating", "[app][web]") {
  const std::string browser = chromium_binary();
  const auto dir = scratch_dir("web-live");
  const int port = free_tcp_port();
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/?token=t0k";
  int rc = -1;
  std::thread run([&] {
    rc = run_luxloc("run --source sim:dense,duration=8 -q --out '" + (dir / "poses.csv").string() + "' --web 127.0.0.1:" +
                    std::to_string(port) + " --web-token t0k --device-id webtest")
             .exit_code;
  });
  for (int i = 0; i < 500 && !port_accepts(port); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  // The page streams until the run ends; with virtual time the DOM is dumped after that.
  const auto r = run_command("timeout 60 '" + browser + "' --headless --disable-gpu --no-sandbox --no-first-run " +
                             "--user-data-dir='" + (dir / "chromium").string() + "' --virtual-time-budget=20000 " +
                             "--dump-dom '" + url + "' 2>/dev/null");
  run.join();
  CHECK(rc == 0);
  const std::string& dom = r.output;
  INFO(dom.substr(0, 4000));
  REQUIRE(r.exit_code == 0);
  CHECK(element_text(dom, "device") == "webtest");
  CHECK(number_of(dom, "map-leds") == 12);          // the dense scenario's LED grid
  CHECK(number_of(dom, "pose-count") >= 20);        // poses arrived...
  CHECK(number_of(dom, "t-span") > 2.0);            // ...over seconds of data: updating
  CHECK(number_of(dom, "trail-points") >= 20);      // the trajectory grew
  CHECK(number_of(dom, "leds-in-view") >= 1);
  CHECK(number_of(dom, "cloud-points") >= 100);   // the particle cloud, subsampled
  CHECK(element_text(dom, "mode") != "-");
  const double x = number_of(dom, "pose-x");
  CHECK(x > 0.0);
  CHECK(x < 8.0);
  std::smatch draws;
  REQUIRE(std::regex_search(dom, draws, std::regex("data-draws=\"([0-9]+)\"")));
  CHECK(std::stoi(draws[1]) >= 20);  // the canvas was redrawn with them
  CHECK(dom.find("<td>sim:dense</td>") != std::string::npos);  // per-source rates table
  // The camera picture: shown, and renewed a few times a second.
  std::smatch frames;
  REQUIRE(std::regex_search(dom, frames, std::regex("<img id=\"camera\"[^>]*data-frames=\"([0-9]+)\"")));
  CHECK(std::stoi(frames[1]) >= 5);
  CHECK(std::regex_search(dom, std::regex("<img id=\"camera\"[^>]*src=\"frame.jpg\\?n=[0-9]+&amp;token=t0k\"")));
}

TEST_CASE("Headless chromium watches a real-time playback of the demo session", "[app][web]") {
  const std::string browser = chromium_binary();
  const auto dir = scratch_dir("web-playback");
  const int port = free_tcp_port();
  const std::string demo = std::string(LUXLOC_SOURCE_DIR) + "/data/demo-walk";
  // 9 s of the 30 s session, then SIGINT: the stream ends and the browser's DOM is dumped
  // (9 s, not 6: under ASan on a busy machine chromium took over 4 s to connect and saw 1.9 s).
  std::thread run([&] {
    run_command("sh -c \"'" + std::string(LUXLOC_BIN) + "' run --playback '" + demo + "' --realtime -q --out /dev/null --web " +
                std::to_string(port) + " & pid=\\$!; sleep 9; kill -INT \\$pid; wait \\$pid\" >/dev/null 2>&1");
  });
  for (int i = 0; i < 500 && !port_accepts(port); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto r = run_command("timeout 60 '" + browser + "' --headless --disable-gpu --no-sandbox --no-first-run " +
                             "--user-data-dir='" + (dir / "chromium").string() + "' --virtual-time-budget=20000 " +
                             "--dump-dom 'http://127.0.0.1:" + std::to_string(port) + "/' 2>/dev/null");
  run.join();
  const std::string& dom = r.output;
  INFO(dom.substr(0, 4000));
  REQUIRE(r.exit_code == 0);
  CHECK(number_of(dom, "map-leds") >= 1);      // the demo room's lights
  CHECK(number_of(dom, "pose-count") >= 20);
  CHECK(number_of(dom, "t-span") > 2.0);
  CHECK(number_of(dom, "trail-points") >= 20);
  CHECK(dom.find("<td>playback:imu</td>") != std::string::npos);
}

TEST_CASE("Bad --web options stop with exit 2 and a message", "[app][web]") {
  const std::string run = "run --source sim:dense,duration=1,realtime=0 -q --out /dev/null ";
  for (const char* bad : {"--web nonsense", "--web 127.0.0.1:0", "--web 10.255.255.1:8080", "--web-token x"}) {
    const auto r = run_luxloc(run + bad);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--web") != std::string::npos);
  }
  // A port somebody else listens on.
  MosquittoBroker taken("web-port-taken");
  const auto r = run_luxloc(run + "--web " + taken.address());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("cannot listen") != std::string::npos);
}
