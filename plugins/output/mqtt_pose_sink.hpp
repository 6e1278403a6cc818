#pragma once
// MQTT pose output (SPEC.md "Pose output", `--mqtt HOST:PORT[/TOPIC]`, repeatable: one sink
// and one broker connection per target), through libmosquitto's threaded client.
//
//   luxloc/<device>/pose    one JSON object per pose: the UDP datagram's flat fields
//                           (pose_json) plus "device":"<device>"; QoS 0, not retained
//   luxloc/<device>/status  once a second, retained, QoS 1: {"device":..,"online":1,
//                           "mode":..,"leds":..,"rates_hz":{source:..},"drops":{..},...};
//                           the broker publishes {"device":..,"online":0} there (the
//                           last will) when the connection dies, and the sink does on a
//                           clean end
//
// Never blocks the filter and never fails the run (it runs on the output thread anyway):
// libmosquitto writes on its own network thread; the poses handed to it and not yet
// written are bounded (MqttOptions::queue_capacity), beyond that a pose is dropped and
// counted ("queue full"), and while there is no connection every pose is dropped and
// counted ("no broker"). The network thread reconnects with a back-off of 1 s doubling to
// 5 s, so a broker that restarts gets the stream again.
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "core/pipeline/pose_sink.hpp"
#include "core/pipeline/run_monitor.hpp"

namespace luxloc {

struct MqttTarget {
  std::string host;
  int port = 1883;
  std::string topic;  // empty: luxloc/<device>/pose
};

// "HOST:PORT", "HOST:PORT/TOPIC", "[IPV6]:PORT[/TOPIC]"; throws InputError (exit 2) with a
// clear message otherwise (no port, bad port, a wildcard or empty level in the topic).
MqttTarget parse_mqtt_target(const std::string& spec);

// The host name (gethostname), "luxloc" when it has none; '/', '+' and '#' (topic
// separators and wildcards) replaced by '_'.
std::string default_device_id();
// Throws InputError unless `id` is usable as one topic level (non-empty, no '/', '+', '#').
void check_device_id(const std::string& id);

// The message body for one pose: pose_json + the device id.
std::string mqtt_pose_json(const PoseEstimate& pose, std::uint64_t seq, const std::string& device);

struct MqttOptions {
  std::string device_id;  // empty: default_device_id()
  std::string tls_ca;     // a CA certificate file: TLS, the broker's certificate checked against it
  std::string user, password;
  std::size_t queue_capacity = 4096;  // messages handed to libmosquitto, not yet written
  int keepalive_s = 10;
  std::chrono::milliseconds status_period{1000};
};

class MqttPoseSink final : public PoseSink {
 public:
  // Checks the spec, resolves the host (InputError for a bad spec or unknown host) and
  // starts connecting in the background: an absent broker is not an error.
  MqttPoseSink(const std::string& spec, MqttOptions options, RunMonitor monitor = {});
  ~MqttPoseSink() override;
  MqttPoseSink(const MqttPoseSink&) = delete;
  MqttPoseSink& operator=(const MqttPoseSink&) = delete;

  std::string name() const override { return "mqtt:" + spec_; }
  void write(const PoseEstimate& pose) override;
  // Waits (at most 2 s, on the output thread) for the poses handed over to be written.
  void flush() override;

  const std::string& pose_topic() const { return pose_topic_; }
  const std::string& status_topic() const { return status_topic_; }
  bool connected() const;
  std::uint64_t published() const;  // poses handed to libmosquitto
  std::uint64_t next_seq() const { return seq_; }

  class Client;  // libmosquitto behind a firewall: its header stays out of ours

 private:
  std::string spec_, pose_topic_, status_topic_, device_;
  std::uint64_t seq_ = 0;
  std::unique_ptr<Client> client_;
};

}  // namespace luxloc
