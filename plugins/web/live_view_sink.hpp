#pragma once
// `--web HOST:PORT`: a read-only live view of the run in the browser, served by the
// binary (cpp-httplib). Two paths and nothing else (no file system, no control):
//   /        the page (plugins/web/live_page.cpp, compiled in)
//   /events  Server-Sent Events: "init" (device, LED map, the trajectory so far), then
//            "pose" (at most every pose_interval), "status" (once a second: rates and
//            drops per source, latency p50/p99, browsers watching) and "frame" (a new
//            camera picture, at most every frame_interval) and "cloud" (a subsample of
//            the particles, as often)
//   /frame.jpg  the last camera frame kept, the identified LEDs circled (CameraSnapshot)
// Any other path is 404; with a token (--web-token) every request without ?token=T is 403.
// Binds 127.0.0.1 unless a host is given ("0.0.0.0:8080" for the network).
//
// Never blocks the filter: it is a pose sink (output thread), and write() only formats an
// event into a bounded ring (EventRing) that the HTTP threads read. A browser that stalls
// is dropped when a write to it times out or when it falls a ring behind; at most
// max_clients event streams at once (more get 503).
#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/common/samples.hpp"
#include "core/pipeline/pose_sink.hpp"
#include "core/pipeline/run_monitor.hpp"
#include "core/vlc/led_observation.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc {

struct WebEndpoint {
  std::string host = "127.0.0.1";
  int port = 0;
};

// "PORT", ":PORT", "HOST:PORT", "[IPV6]:PORT"; throws InputError (exit 2) otherwise.
WebEndpoint parse_web_endpoint(const std::string& spec);

struct LiveViewOptions {
  std::string token;      // non-empty: required as ?token= on every request
  std::string device_id;  // shown on the page
  std::size_t ring_capacity = 512;
  std::chrono::milliseconds pose_interval{50};  // at most 20 poses a second to the browsers
  std::chrono::milliseconds status_interval{1000};
  std::chrono::milliseconds frame_interval{333};  // about 3 camera pictures a second
  std::chrono::seconds write_timeout{2};
  std::size_t max_clients = 6;  // event streams at once (cpp-httplib serves from 8 threads)
  std::size_t history = 5000;   // trajectory points a new browser gets
};

class LiveViewSink final : public PoseSink {
 public:
  // Binds and starts serving (InputError when the address cannot be bound).
  LiveViewSink(const std::string& spec, LiveViewOptions options, RunMonitor monitor = {},
               const std::optional<LedMap>& map = std::nullopt);
  ~LiveViewSink() override;
  LiveViewSink(const LiveViewSink&) = delete;
  LiveViewSink& operator=(const LiveViewSink&) = delete;

  std::string name() const override { return "web:" + spec_; }
  void write(const PoseEstimate& pose) override;
  // The fusion thread (FusionEngine::set_frame_observer): keeps a copy now and then.
  void offer_frame(const FrameSample& frame, const std::vector<LedObservation>& leds);
  // The fusion thread (FusionEngine::set_cloud_observer): a "cloud" event for the browsers.
  void offer_cloud(const std::vector<Eigen::Vector2d>& particles);

  int port() const;
  std::string url() const;  // http://HOST:PORT/ (with ?token=)
  std::uint64_t clients_served() const;   // event streams opened
  std::uint64_t clients_dropped() const;  // streams closed because the browser stalled

  class Server;

 private:
  std::string spec_;
  std::unique_ptr<Server> server_;
};

}  // namespace luxloc
