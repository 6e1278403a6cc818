#include "plugins/output/mqtt_pose_sink.hpp"

#include <mosquitto.h>
#include <netdb.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "core/common/input_error.hpp"
#include "core/pipeline/latency_stats.hpp"
#include "plugins/output/json_text.hpp"
#include "plugins/output/pose_text.hpp"
#include "plugins/output/udp_pose_sink.hpp"

namespace luxloc {
namespace {

InputError bad_target(const std::string& spec, const std::string& why) {
  return InputError("--mqtt", 0, "", "'" + spec + "': " + why +
                                         " (expected HOST:PORT[/TOPIC], e.g. 127.0.0.1:1883 or "
                                         "broker.local:1883/site/cart7/pose)");
}

void check_topic(const std::string& spec, const std::string& topic) {
  if (topic.empty()) throw bad_target(spec, "empty topic after '/'");
  if (topic.find_first_of("+#") != std::string::npos) throw bad_target(spec, "a topic to publish on has no wildcards ('+', '#')");
  if (topic.find('\0') != std::string::npos) throw bad_target(spec, "NUL in the topic");
  if (topic.size() > 65535) throw bad_target(spec, "topic longer than 65535 bytes");
}

std::once_flag g_lib_init;

}  // namespace

MqttTarget parse_mqtt_target(const std::string& spec) {
  // The topic starts at the first '/' after the port (no '/' in a host or an IPv6 literal).
  const std::size_t slash = spec.find('/');
  const std::string host_port = spec.substr(0, slash);
  UdpEndpoint e;
  try {
    e = parse_udp_endpoint(host_port);
  } catch (const InputError& err) {
    // Same rules as --udp; say it in --mqtt's words.
    const std::string what = err.what();
    const auto colon = what.find("': ");
    const auto paren = what.rfind(" (expected");
    throw bad_target(spec, colon != std::string::npos && paren != std::string::npos && paren > colon
                               ? what.substr(colon + 3, paren - colon - 3)
                               : "bad HOST:PORT");
  }
  MqttTarget t;
  t.host = e.host;
  t.port = std::stoi(e.port);
  if (slash != std::string::npos) {
    t.topic = spec.substr(slash + 1);
    check_topic(spec, t.topic);
  }
  return t;
}

std::string default_device_id() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "luxloc";
  std::string id(buf);
  for (char& ch : id)
    if (ch == '/' || ch == '+' || ch == '#') ch = '_';
  return id;
}

void check_device_id(const std::string& id) {
  if (id.empty()) throw InputError("--device-id", 0, "", "empty device id");
  if (id.find_first_of("/+#") != std::string::npos || id.find('\0') != std::string::npos)
    throw InputError("--device-id", 0, "", "'" + id + "': a device id is one MQTT topic level: no '/', '+' or '#'");
}

std::string mqtt_pose_json(const PoseEstimate& pose, std::uint64_t seq, const std::string& device) {
  std::string s = pose_json(pose, seq);
  s.pop_back();  // the closing '}'
  s += ",\"device\":";
  s += json_string(device);
  s += '}';
  return s;
}

// The libmosquitto client, its callbacks (on libmosquitto's network thread) and the status
// thread. Counters are atomics: write() runs on the pipeline's output thread.
class MqttPoseSink::Client {
 public:
  Client(const MqttTarget& target, MqttOptions options, RunMonitor monitor, std::string status_topic,
         std::string spec, DropCounts& drops)
      : options_(std::move(options)),
        monitor_(std::move(monitor)),
        status_topic_(std::move(status_topic)),
        spec_(std::move(spec)),
        drops_(drops) {
    std::call_once(g_lib_init, [] { mosquitto_lib_init(); });
    mosq_ = mosquitto_new(nullptr, true, this);
    if (!mosq_) throw std::runtime_error("mqtt: cannot create a libmosquitto client");
    mosquitto_int_option(mosq_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
    mosquitto_int_option(mosq_, MOSQ_OPT_TCP_NODELAY, 1);  // a pose is small and wanted now
    mosquitto_connect_callback_set(mosq_, on_connect);
    mosquitto_disconnect_callback_set(mosq_, on_disconnect);
    mosquitto_publish_callback_set(mosq_, on_publish);
    const std::string will = offline_json();
    mosquitto_will_set(mosq_, status_topic_.c_str(), static_cast<int>(will.size()), will.data(), 1, true);
    if (!options_.user.empty() &&
        mosquitto_username_pw_set(mosq_, options_.user.c_str(),
                                  options_.password.empty() ? nullptr : options_.password.c_str()) != MOSQ_ERR_SUCCESS)
      throw InputError("--mqtt-user", 0, "", "libmosquitto refused the user name");
    if (!options_.tls_ca.empty()) {
      const int rc = mosquitto_tls_set(mosq_, options_.tls_ca.c_str(), nullptr, nullptr, nullptr, nullptr);
      if (rc != MOSQ_ERR_SUCCESS)
        throw InputError("--mqtt-tls-ca", 0, "", "'" + options_.tls_ca + "': " + mosquitto_strerror(rc));
    }
    mosquitto_reconnect_delay_set(mosq_, 1, 5, true);
    // A broker that is not there yet is not an error: the network thread retries.
    mosquitto_connect_async(mosq_, target.host.c_str(), target.port, options_.keepalive_s);
    if (const int rc = mosquitto_loop_start(mosq_); rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      throw std::runtime_error(std::string("mqtt: cannot start the network thread: ") + mosquitto_strerror(rc));
    }
    status_thread_ = std::thread([this] { status_loop(); });
  }

  ~Client() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    status_thread_.join();
    if (connected_.load()) {
      const std::string off = offline_json();
      publish(status_topic_, off, 1, true);
      drain(std::chrono::milliseconds(1000));
    }
    mosquitto_disconnect(mosq_);
    mosquitto_loop_stop(mosq_, false);
    mosquitto_destroy(mosq_);
  }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool connected() const { return connected_.load(std::memory_order_acquire); }
  std::uint64_t poses() const { return poses_.load(std::memory_order_relaxed); }

  // The output thread's side: hand one pose over, or count why not.
  void publish_pose(const std::string& topic, const std::string& body, const PoseEstimate& pose) {
    {
      std::lock_guard lock(mutex_);
      last_pose_ = pose;
      have_pose_ = true;
      latency_.add(pose.latency_s);
    }
    if (!connected()) {
      drops_.add("no broker", "mqtt:" + spec_ + ": not connected");
      return;
    }
    if (handed_.load(std::memory_order_relaxed) - written_.load(std::memory_order_acquire) >= options_.queue_capacity) {
      drops_.add("queue full", "mqtt:" + spec_ + ": broker too slow");
      return;
    }
    const int rc = publish(topic, body, 0, false);
    if (rc == MOSQ_ERR_SUCCESS)
      poses_.fetch_add(1, std::memory_order_relaxed);
    else if (rc == MOSQ_ERR_NO_CONN)
      drops_.add("no broker", "mqtt:" + spec_ + ": " + mosquitto_strerror(rc));
    else
      drops_.add("send error", "mqtt:" + spec_ + ": " + mosquitto_strerror(rc));
  }

  // Waits until libmosquitto has written everything handed to it (or the connection is gone).
  void drain(std::chrono::milliseconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (connected() && written_.load() < handed_.load() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }

 private:
  int publish(const std::string& topic, const std::string& body, int qos, bool retain) {
    handed_.fetch_add(1, std::memory_order_relaxed);
    const int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(body.size()), body.data(), qos, retain);
    if (rc != MOSQ_ERR_SUCCESS) written_.fetch_add(1, std::memory_order_relaxed);  // never queued
    return rc;
  }

  static void on_connect(mosquitto*, void* self, int rc) {
    auto* c = static_cast<Client*>(self);
    if (rc != 0) return;
    // Whatever was queued before a reconnect is gone with the old connection.
    c->written_.store(c->handed_.load());
    c->connected_.store(true, std::memory_order_release);
    c->wake_.notify_all();  // the retained status now, not in up to a second
  }
  static void on_disconnect(mosquitto*, void* self, int) {
    static_cast<Client*>(self)->connected_.store(false, std::memory_order_release);
  }
  static void on_publish(mosquitto*, void* self, int) {
    static_cast<Client*>(self)->written_.fetch_add(1, std::memory_order_release);
  }

  std::string offline_json() const {
    return "{\"device\":" + json_string(options_.device_id) + ",\"online\":0}";
  }

  void status_loop() {
    using Clock = std::chrono::steady_clock;
    std::vector<std::uint64_t> last_counts(monitor_.source_names.size(), 0);
    auto last = Clock::now();
    bool was_connected = false;
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      wake_.wait_for(lock, options_.status_period, [&] { return stopping_ || (connected() && !was_connected); });
      if (stopping_) break;
      was_connected = connected();
      const auto now = Clock::now();
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      JsonObject s;
      s.add_string("device", options_.device_id);
      s.add_number("online", "1");
      if (have_pose_) {
        s.add_number("t", format_time_s(last_pose_.t, 6));
        s.add_number("x", format_fixed(last_pose_.p_BinW.x(), 3));
        s.add_number("y", format_fixed(last_pose_.p_BinW.y(), 3));
        s.add_number("sigma_x", format_fixed(last_pose_.sigma_x, 3));
        s.add_number("sigma_y", format_fixed(last_pose_.sigma_y, 3));
        s.add_number("leds", std::to_string(last_pose_.leds));
        if (!last_pose_.mode.empty()) s.add_string("mode", last_pose_.mode);
        if (!last_pose_.motion.empty()) s.add_string("motion", last_pose_.motion);
      }
      s.add_number("poses", std::to_string(poses()));
      if (const LatencySummary l = latency_.summary(); l.count > 0) {
        s.add_number("latency_p50_ms", format_fixed(1e3 * l.p50_s, 3));
        s.add_number("latency_p99_ms", format_fixed(1e3 * l.p99_s, 3));
      }
      JsonObject rates, source_drops;
      for (std::size_t i = 0; i < monitor_.source_names.size(); ++i) {
        if (monitor_.counters && i < monitor_.counters->size()) {
          const std::uint64_t c = monitor_.counters->count(i);
          rates.add_number(monitor_.source_names[i], format_fixed(dt > 0 ? static_cast<double>(c - last_counts[i]) / dt : 0.0, 1));
          last_counts[i] = c;
        }
        if (i < monitor_.source_drops.size() && monitor_.source_drops[i])
          source_drops.add_number(monitor_.source_names[i], std::to_string(monitor_.source_drops[i]->total()));
      }
      s.add_object("rates_hz", rates);
      s.add_object("source_drops", source_drops);
      JsonObject own;
      for (const auto& [reason, e] : drops_.snapshot()) own.add_number(reason, std::to_string(e.count));
      s.add_object("mqtt_drops", own);
      const std::string body = s.str();
      lock.unlock();
      if (connected()) publish(status_topic_, body, 1, true);
      lock.lock();
    }
  }

  MqttOptions options_;
  RunMonitor monitor_;
  std::string status_topic_, spec_;
  DropCounts& drops_;
  mosquitto* mosq_ = nullptr;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> handed_{0}, written_{0}, poses_{0};
  std::mutex mutex_;  // last_pose_, have_pose_, latency_, stopping_
  std::condition_variable wake_;
  PoseEstimate last_pose_;
  bool have_pose_ = false;
  LatencyWindow latency_{1024};
  bool stopping_ = false;
  std::thread status_thread_;
};

MqttPoseSink::MqttPoseSink(const std::string& spec, MqttOptions options, RunMonitor monitor) : spec_(spec) {
  const MqttTarget target = parse_mqtt_target(spec);
  if (options.device_id.empty()) options.device_id = default_device_id();
  check_device_id(options.device_id);
  {  // An unknown host is a typo (exit 2); a known one without a broker is just absent.
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = getaddrinfo(target.host.c_str(), nullptr, &hints, &found); rc != 0)
      throw InputError("--mqtt", 0, "", "'" + spec + "': cannot resolve host '" + target.host + "': " + gai_strerror(rc));
    freeaddrinfo(found);
  }
  if (!options.tls_ca.empty() && ::access(options.tls_ca.c_str(), R_OK) != 0)
    throw InputError("--mqtt-tls-ca", 0, "", "'" + options.tls_ca + "': cannot read the CA certificate file");
  pose_topic_ = target.topic.empty() ? "luxloc/" + options.device_id + "/pose" : target.topic;
  status_topic_ = "luxloc/" + options.device_id + "/status";
  device_ = options.device_id;
  client_ = std::make_unique<Client>(target, std::move(options), std::move(monitor), status_topic_, spec_, drops());
}

MqttPoseSink::~MqttPoseSink() = default;

void MqttPoseSink::write(const PoseEstimate& pose) {
  client_->publish_pose(pose_topic_, mqtt_pose_json(pose, seq_++, device_), pose);
}

void MqttPoseSink::flush() { client_->drain(std::chrono::milliseconds(2000)); }

bool MqttPoseSink::connected() const { return client_->connected(); }
std::uint64_t MqttPoseSink::published() const { return client_->poses(); }

}  // namespace luxloc
