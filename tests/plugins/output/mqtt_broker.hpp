#pragma once
// Test helpers for the MQTT output: a real mosquitto broker on a free loopback port (a
// child process with its own config file in a scratch folder) and a libmosquitto
// subscriber that records what arrives. A missing mosquitto binary FAILS the test, with
// a message: the MQTT tests are never skipped.
#include <arpa/inet.h>
#include <fcntl.h>
#include <mosquitto.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

extern char** environ;

namespace luxloc::test {

// A loopback TCP port nobody listens on right now (the kernel picks it).
inline int free_tcp_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  socklen_t len = sizeof a;
  REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
  ::close(fd);
  return ntohs(a.sin_port);
}

inline bool port_accepts(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  ::close(fd);
  return ok;
}

inline std::string mosquitto_binary() {
  for (const char* p : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"})
    if (::access(p, X_OK) == 0) return p;
  FAIL("the mosquitto broker is not installed (Debian package 'mosquitto'; scripts/setup.sh installs it)");
  return {};
}

class MosquittoBroker {
 public:
  explicit MosquittoBroker(const std::string& name, int port = 0) : port_(port ? port : free_tcp_port()) {
    dir_ = scratch_dir("mqtt-" + name + "-" + std::to_string(::getpid()));
    start();
  }
  ~MosquittoBroker() { stop(); }
  MosquittoBroker(const MosquittoBroker&) = delete;
  MosquittoBroker& operator=(const MosquittoBroker&) = delete;

  int port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string log() const { return read_text(dir_ / "broker.log"); }  // for a failing check's INFO

  void start() {
    const std::string bin = mosquitto_binary();
    const auto conf = dir_ / "mosquitto.conf";
    {
      std::ofstream c(conf);
      c << "listener " << port_ << " 127.0.0.1\nallow_anonymous true\npersistence false\n"
        << "log_dest stderr\n";  // a root broker drops to user mosquitto: it could not open a file here
    }
    const std::string conf_s = conf.string();
    std::vector<char*> argv{const_cast<char*>(bin.c_str()), const_cast<char*>("-c"), const_cast<char*>(conf_s.c_str()),
                            nullptr};
    const std::string log_file = (dir_ / "broker.log").string();
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 2, log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_addopen(&files, 1, "/dev/null", O_WRONLY, 0);
    const int rc = posix_spawn(&pid_, bin.c_str(), &files, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    REQUIRE(rc == 0);
    for (int i = 0; i < 200 && !port_accepts(port_); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    INFO("broker log: " << log());
    REQUIRE(port_accepts(port_));
  }
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  int port_;
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

struct MqttMessage {
  std::string topic, payload;
  bool retained = false;
  std::chrono::steady_clock::time_point at;
};

// Subscribes to `topic` (wildcards allowed) and records every message.
class MqttSubscriber {
 public:
  MqttSubscriber(int port, std::string topic) : topic_(std::move(topic)) {
    mosquitto_lib_init();
    mosq_ = mosquitto_new(nullptr, true, this);
    REQUIRE(mosq_ != nullptr);
    mosquitto_connect_callback_set(mosq_, [](mosquitto* m, void* self, int rc) {
      auto* s = static_cast<MqttSubscriber*>(self);
      if (rc == 0) mosquitto_subscribe(m, nullptr, s->topic_.c_str(), 1);
    });
    mosquitto_subscribe_callback_set(mosq_, [](mosquitto*, void* self, int, int, const int*) {
      static_cast<MqttSubscriber*>(self)->subscribed_ = true;
    });
    mosquitto_message_callback_set(mosq_, [](mosquitto*, void* self, const mosquitto_message* m) {
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard lock(s->mutex_);
      s->messages_.push_back({m->topic, std::string(static_cast<const char*>(m->payload), static_cast<std::size_t>(m->payloadlen)),
                              m->retain, std::chrono::steady_clock::now()});
    });
    mosquitto_reconnect_delay_set(mosq_, 1, 1, false);
    REQUIRE(mosquitto_connect(mosq_, "127.0.0.1", port, 10) == MOSQ_ERR_SUCCESS);
    REQUIRE(mosquitto_loop_start(mosq_) == MOSQ_ERR_SUCCESS);
    for (int i = 0; i < 200 && !subscribed_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(subscribed_);
  }
  ~MqttSubscriber() {
    mosquitto_disconnect(mosq_);
    mosquitto_loop_stop(mosq_, false);
    mosquitto_destroy(mosq_);
  }
  MqttSubscriber(const MqttSubscriber&) = delete;
  MqttSubscriber& operator=(const MqttSubscriber&) = delete;

  std::vector<MqttMessage> messages() {
    std::lock_guard lock(mutex_);
    return messages_;
  }
  std::vector<MqttMessage> on(const std::string& topic) {
    std::vector<MqttMessage> out;
    for (auto& m : messages())
      if (m.topic == topic) out.push_back(m);
    return out;
  }
  // Waits until `n` messages arrived on `topic` (or the timeout).
  bool wait_for(const std::string& topic, std::size_t n, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (on(topic).size() < n) {
      if (std::chrono::steady_clock::now() > until) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }
  // Waits until a message on `topic` whose payload satisfies `accept` arrived (or the timeout).
  template <class Accept>
  bool wait_until(const std::string& topic, Accept accept, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      for (const auto& m : on(topic))
        if (accept(m.payload)) return true;
      if (std::chrono::steady_clock::now() > until) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

 private:
  std::string topic_;
  mosquitto* mosq_ = nullptr;
  std::atomic<bool> subscribed_{false};
  std::mutex mutex_;
  std::vector<MqttMessage> messages_;
};

// The value of a numeric or string field of a JSON text, as written (no parsing of the
// whole object): "" when absent.
inline std::string json_field(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\":";
  const auto at = json.find(k);
  if (at == std::string::npos) return {};
  auto v = at + k.size();
  if (json[v] == '"') return json.substr(v + 1, json.find('"', v + 1) - v - 1);
  const auto end = json.find_first_of(",}", v);
  return json.substr(v, end - v);
}

}  // namespace luxloc::test
