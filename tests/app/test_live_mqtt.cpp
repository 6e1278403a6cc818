// `luxloc run --mqtt` against a real mosquitto broker on a loopback port: a real-time
// playback's poses (rate, sequence, content), the retained status and the last will when
// the process dies, a run without a broker, and bad options.
#include <catch2/catch.hpp>
#include <algorithm>
#include <map>
#include <cstdlib>
#include <thread>

#include "plugins/output/mqtt_broker.hpp"
#include "plugins/output/udp_receiver.hpp"
#include "test_support.hpp"

using namespace luxloc::test;

namespace {

std::string demo_dir() { return std::string(LUXLOC_SOURCE_DIR) + "/data/demo-walk"; }

// `luxloc run ARGS` in the background for `seconds`, then `signal`; returns the exit code.
int run_for(const std::string& args, double seconds, const char* signal) {
  const std::string cmd = "sh -c \"'" + std::string(LUXLOC_BIN) + "' run " + args + " & pid=\\$!; sleep " +
                          std::to_string(seconds) + "; kill -" + signal + " \\$pid; wait \\$pid\" >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("A live luxloc run publishes every pose at the output rate to a real MQTT broker", "[app][io][mqtt]") {
  MosquittoBroker broker("live");
  MqttSubscriber sub(broker.port(), "luxloc/#");
  const int rc = run_for("--playback '" + demo_dir() + "' --realtime -q --device-id cart7 --mqtt " + broker.address(),
                         2.5, "INT");
  CHECK(rc == 0);
  // The offline status is the last thing luxloc publishes; wait for it, not for a count
  // (online statuses come about once a second, so a count can be met before it arrives).
  const auto offline = [](const std::string& p) { return json_field(p, "online") == "0"; };
  CHECK(sub.wait_until("luxloc/cart7/status", offline, std::chrono::seconds(5)));
  const auto poses = sub.on("luxloc/cart7/pose");
  REQUIRE(poses.size() > 50);
  std::vector<std::map<std::string, double>> parsed;
  for (const auto& m : poses) {
    INFO(m.payload);
    CHECK(json_field(m.payload, "device") == "cart7");
    std::string numeric = m.payload;
    numeric.erase(numeric.find(",\"device\":"));  // the flat numeric part (the UDP datagram)
    parsed.push_back(parse_flat_json(numeric + "}"));
  }
  for (const char* key : {"t", "x", "y", "z", "yaw", "sigma_x", "sigma_y", "seq"}) CHECK(parsed.front().count(key) == 1);
  CHECK(parsed.front().at("seq") == 0);
  for (std::size_t i = 1; i < parsed.size(); ++i) {
    CHECK(parsed[i].at("seq") == parsed[i - 1].at("seq") + 1);  // nothing lost, in order
    CHECK(parsed[i].at("t") > parsed[i - 1].at("t"));
  }
  const double span = parsed.back().at("t") - parsed.front().at("t");
  CHECK(static_cast<double>(parsed.size() - 1) / span == Approx(50.0).epsilon(0.05));
  CHECK(span > 1.5);
  CHECK(span < 3.0);  // paced
  for (const auto& p : parsed) {
    CHECK(p.at("x") > -1.0);
    CHECK(p.at("x") < 9.0);
  }
  const auto status = sub.on("luxloc/cart7/status");
  REQUIRE(status.size() >= 2);  // about one a second, then offline at the end
  INFO(status.front().payload);
  CHECK(status.front().payload.find("\"rates_hz\":{\"playback:imu\":") != std::string::npos);
  CHECK(json_field(status.back().payload, "online") == "0");
}

TEST_CASE("The broker publishes luxloc's last will when the process dies", "[app][io][mqtt]") {
  MosquittoBroker broker("will");
  MqttSubscriber sub(broker.port(), "luxloc/dying/status");
  const int rc = run_for("--playback '" + demo_dir() + "' --realtime -q --device-id dying --mqtt " + broker.address(),
                         2.0, "KILL");
  CHECK(rc != 0);
  // Wait for the will itself: the online statuses luxloc sent before the kill (about one a
  // second) can reach any count first, so counting messages raced the broker's will.
  const auto offline = [](const std::string& p) { return json_field(p, "online") == "0"; };
  REQUIRE(sub.wait_until("luxloc/dying/status", offline, std::chrono::seconds(5)));
  const auto status = sub.on("luxloc/dying/status");
  CHECK(json_field(status.front().payload, "online") == "1");
  CHECK(json_field(status.back().payload, "online") == "0");
  CHECK(json_field(status.back().payload, "device") == "dying");
}

TEST_CASE("A run with --mqtt and no broker goes on and writes every pose to --out", "[app][io][mqtt]") {
  const auto dir = scratch_dir("mqtt-no-broker");
  const auto out = (dir / "poses.csv").string();
  const auto ref = (dir / "ref.csv").string();
  const int port = free_tcp_port();
  const auto r = run_luxloc("run --playback '" + demo_dir() + "' --out '" + out + "' --mqtt 127.0.0.1:" +
                            std::to_string(port));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // Said at the end: how many poses the broker did not get, and why.
  CHECK(r.output.find("output mqtt:127.0.0.1:" + std::to_string(port) + ": ") != std::string::npos);
  CHECK(r.output.find("poses not delivered (no broker)") != std::string::npos);
  const auto base = run_luxloc("run --playback '" + demo_dir() + "' -q --out '" + ref + "'");
  REQUIRE(base.exit_code == 0);
  const std::string poses = read_text(out);
  CHECK(std::count(poses.begin(), poses.end(), '\n') > 1000);
  CHECK(poses == read_text(ref));  // the broker's absence changes nothing
}

TEST_CASE("Bad MQTT options stop with exit 2 and a message", "[app][io][mqtt]") {
  const std::string demo = "run --playback '" + demo_dir() + "' -q --out /dev/null ";
  for (const char* bad : {"--mqtt localhost", "--mqtt localhost:99999", "--mqtt 127.0.0.1:1883/a/#",
                          "--mqtt no-such-host.invalid:1883", "--mqtt 127.0.0.1:1883 --device-id a/b",
                          "--mqtt 127.0.0.1:1883 --mqtt-tls-ca /no/such/ca.pem"}) {
    const auto r = run_luxloc(demo + bad);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK((r.output.find("--mqtt") != std::string::npos || r.output.find("--device-id") != std::string::npos));
  }
}
