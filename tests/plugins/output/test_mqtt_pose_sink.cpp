// The MQTT pose output against a real mosquitto broker on a loopback port: targets,
// content, sequence, retained status, no broker, broker restart.
#include <catch2/catch.hpp>

#include "core/common/input_error.hpp"
#include "mqtt_broker.hpp"
#include "plugins/output/mqtt_pose_sink.hpp"
#include "udp_receiver.hpp"

using namespace luxloc;
using namespace luxloc::test;

namespace {

PoseEstimate pose_at(int k) {
  PoseEstimate p;
  p.t = seconds_to_ns(100.0 + 0.02 * k);
  p.p_BinW = {1.0 + 0.01 * k, 2.0, 1.2};
  p.yaw = 0.5;
  p.sigma_x = 0.05;
  p.sigma_y = 0.06;
  p.leds = 3;
  p.mode = "tracking";
  return p;
}

MqttOptions options(const std::string& id) {
  MqttOptions o;
  o.device_id = id;
  o.status_period = std::chrono::milliseconds(200);
  return o;
}

}  // namespace

TEST_CASE("MQTT targets are HOST:PORT with an optional topic, and bad ones are refused", "[plugins][output][mqtt]") {
  MqttTarget t = parse_mqtt_target("127.0.0.1:1883");
  CHECK(t.host == "127.0.0.1");
  CHECK(t.port == 1883);
  CHECK(t.topic.empty());
  t = parse_mqtt_target("broker.local:8883/site/cart7/pose");
  CHECK(t.host == "broker.local");
  CHECK(t.port == 8883);
  CHECK(t.topic == "site/cart7/pose");
  t = parse_mqtt_target("[::1]:1884/x");
  CHECK(t.host == "::1");
  CHECK(t.port == 1884);
  CHECK(t.topic == "x");
  for (const char* bad : {"", "localhost", "localhost:", ":1883", "host:0", "host:70000", "host:abc", "host:1883/",
                          "host:1883/a/+/b", "host:1883/a/#", "::1:1883"}) {
    INFO(bad);
    CHECK_THROWS_AS(parse_mqtt_target(bad), InputError);
  }
  CHECK_THROWS_WITH(parse_mqtt_target("host:1883/a/#"), Catch::Contains("--mqtt") && Catch::Contains("wildcard"));
  CHECK_THROWS_AS(check_device_id("a/b"), InputError);
  CHECK_THROWS_AS(check_device_id(""), InputError);
  CHECK_NOTHROW(check_device_id("cart-7"));
  CHECK(default_device_id().find('/') == std::string::npos);
}

TEST_CASE("An MQTT pose message is the UDP datagram's JSON plus the device id", "[plugins][output][mqtt]") {
  const std::string j = mqtt_pose_json(pose_at(0), 7, "cart \"7\"");
  CHECK(j.rfind("{\"t\":100.000000,", 0) == 0);
  CHECK(j.find("\"seq\":7,\"device\":\"cart \\\"7\\\"\"}") != std::string::npos);
}

TEST_CASE("The MQTT sink publishes every pose in order to a real broker, and a retained status", "[plugins][output][mqtt]") {
  MosquittoBroker broker("content");
  MqttSubscriber sub(broker.port(), "luxloc/#");
  auto counters = std::make_shared<SampleCounters>(1);
  RunMonitor monitor{{"playback:imu"}, counters, {}};
  {
    MqttPoseSink sink(broker.address(), options("unit1"), monitor);
    CHECK(sink.pose_topic() == "luxloc/unit1/pose");
    CHECK(sink.status_topic() == "luxloc/unit1/status");
    for (int i = 0; i < 200 && !sink.connected(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(sink.connected());
    for (int k = 0; k < 500; ++k) {
      counters->add(0);
      sink.write(pose_at(k));
    }
    sink.flush();
    CHECK(sink.published() == 500);
    CHECK(sink.drops().total() == 0);
    REQUIRE(sub.wait_for("luxloc/unit1/pose", 500, std::chrono::seconds(5)));
    REQUIRE(sub.wait_for("luxloc/unit1/status", 1, std::chrono::seconds(3)));
  }
  const auto poses = sub.on("luxloc/unit1/pose");
  REQUIRE(poses.size() == 500);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    INFO(poses[k].payload);
    CHECK(json_field(poses[k].payload, "seq") == std::to_string(k));
    CHECK(json_field(poses[k].payload, "device") == "unit1");
    CHECK(std::stod(json_field(poses[k].payload, "x")) == Approx(1.0 + 0.01 * static_cast<double>(k)));
    CHECK(json_field(poses[k].payload, "sigma_y") == "0.06000");
  }
  // The clean end says offline, retained: a late subscriber learns the device is gone.
  std::vector<MqttMessage> status;
  for (int i = 0; i < 200; ++i) {
    status = sub.on("luxloc/unit1/status");
    if (!status.empty() && json_field(status.back().payload, "online") == "0") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  REQUIRE(status.size() >= 2);
  const std::string& first = status.front().payload;
  INFO(first);
  CHECK(json_field(first, "device") == "unit1");
  CHECK(json_field(first, "online") == "1");
  CHECK(first.find("\"rates_hz\":{\"playback:imu\":") != std::string::npos);
  CHECK(json_field(status.back().payload, "online") == "0");
  MqttSubscriber late(broker.port(), "luxloc/unit1/status");
  REQUIRE(late.wait_for("luxloc/unit1/status", 1, std::chrono::seconds(3)));
  CHECK(late.messages().front().retained);
  CHECK(json_field(late.messages().front().payload, "online") == "0");
}

TEST_CASE("Without a broker the MQTT sink never blocks and counts every pose as dropped", "[plugins][output][mqtt]") {
  const int port = free_tcp_port();  // nobody listens there
  MqttPoseSink sink("127.0.0.1:" + std::to_string(port), options("nobroker"));
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 10000; ++k) sink.write(pose_at(k));
  sink.flush();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(s < 1.0);
  CHECK(!sink.connected());
  CHECK(sink.drops().count("no broker") == 10000);
  CHECK(sink.next_seq() == 10000);
}

TEST_CASE("The MQTT sink reconnects when the broker comes back, and the stream goes on", "[plugins][output][mqtt]") {
  auto broker = std::make_unique<MosquittoBroker>("restart");
  const int port = broker->port();
  MqttPoseSink sink(broker->address(), options("restart1"));
  for (int i = 0; i < 200 && !sink.connected(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(sink.connected());
  int k = 0;
  for (; k < 50; ++k) sink.write(pose_at(k));
  sink.flush();
  broker->stop();  // SIGKILL: the connection just dies
  for (int i = 0; i < 300 && sink.connected(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK(!sink.connected());
  for (int i = 0; i < 50; ++i) sink.write(pose_at(k++));
  CHECK(sink.drops().count("no broker") >= 50);
  broker = std::make_unique<MosquittoBroker>("restart", port);
  MqttSubscriber sub(port, "luxloc/restart1/#");
  // Back-off of 1 s doubling to 5 s: back within a few seconds.
  for (int i = 0; i < 1500 && !sink.connected(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(sink.connected());
  // The new broker learns at once that the device is online again (the status is sent on
  // connect, not at the next period).
  CHECK(sub.wait_until("luxloc/restart1/status", [](const std::string& s) { return json_field(s, "online") == "1"; },
                       std::chrono::seconds(3)));
  const int resumed_at = k;
  for (int i = 0; i < 50; ++i) sink.write(pose_at(k++));
  sink.flush();
  const bool all_arrived = sub.wait_for("luxloc/restart1/pose", 50, std::chrono::seconds(5));
  // A failure says where the poses went: never handed over, dropped (and why), or lost after.
  INFO("arrived " << sub.on("luxloc/restart1/pose").size() << " of 50; the sink handed over " << sink.published()
                  << " in all (50 before the restart), connected " << sink.connected() << ", no broker "
                  << sink.drops().count("no broker") << ", queue full " << sink.drops().count("queue full")
                  << ", send error " << sink.drops().count("send error") << "\nbroker log:\n"
                  << broker->log());
  REQUIRE(all_arrived);
  const auto got = sub.on("luxloc/restart1/pose");
  CHECK(json_field(got.front().payload, "seq") == std::to_string(resumed_at));
  CHECK(json_field(got.back().payload, "seq") == std::to_string(k - 1));
}
