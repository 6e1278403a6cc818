#include "plugins/web/live_view_sink.hpp"

#include <httplib.h>

#include <atomic>
#include <cmath>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "core/common/input_error.hpp"
#include "core/pipeline/latency_stats.hpp"
#include "plugins/output/json_text.hpp"
#include "plugins/output/pose_text.hpp"
#include "plugins/output/udp_pose_sink.hpp"
#include "plugins/web/camera_snapshot.hpp"
#include "plugins/web/event_ring.hpp"
#include "plugins/web/live_page.hpp"

namespace luxloc {
namespace {

// Compares without stopping at the first difference (a token's prefix is not learnt by timing).
bool same_token(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ (i < b.size() ? b[i] : 0));
  return diff == 0;
}

std::string sse(const char* event, const std::string& data) { return std::string("event: ") + event + "\ndata: " + data + "\n\n"; }

}  // namespace

WebEndpoint parse_web_endpoint(const std::string& spec) {
  std::string hp = spec;
  if (!spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos) hp = "127.0.0.1:" + spec;
  else if (!spec.empty() && spec.front() == ':') hp = "127.0.0.1" + spec;
  try {
    const UdpEndpoint e = parse_udp_endpoint(hp);
    return WebEndpoint{e.host, std::stoi(e.port)};
  } catch (const InputError&) {
    throw InputError("--web", 0, "", "'" + spec + "': expected [HOST:]PORT, e.g. 8080 (127.0.0.1), 0.0.0.0:8080 (every "
                                     "interface) or [::1]:8080");
  }
}

class LiveViewSink::Server {
 public:
  Server(const WebEndpoint& at, LiveViewOptions options, RunMonitor monitor, const std::optional<LedMap>& map)
      : options_(std::move(options)),
        monitor_(std::move(monitor)),
        ring_(options_.ring_capacity),
        camera_(options_.frame_interval),
        host_(at.host) {
    JsonObject init;
    std::string leds = "[";
    if (map)
      for (const Led& l : map->leds()) {
        JsonObject o;
        o.add_number("id", std::to_string(l.id));
        o.add_number("f", format_fixed(l.freq_hz, 1));
        o.add_number("x", format_fixed(l.p_inW.x(), 3));
        o.add_number("y", format_fixed(l.p_inW.y(), 3));
        o.add_number("z", format_fixed(l.p_inW.z(), 3));
        leds += (leds.size() > 1 ? "," : "") + o.str();
      }
    leds_json_ = leds + "]";
    last_counts_.assign(monitor_.source_names.size(), 0);

    http_.set_write_timeout(options_.write_timeout);
    http_.set_keep_alive_max_count(20);
    // The token guards every path, the page included.
    http_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      if (options_.token.empty() || same_token(req.get_param_value("token"), options_.token))
        return httplib::Server::HandlerResponse::Unhandled;
      res.status = 403;
      res.set_content("forbidden: this live view needs ?token=\n", "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    });
    http_.set_error_handler([](const httplib::Request&, httplib::Response& res) {
      if (res.body.empty()) res.set_content(std::to_string(res.status) + "\n", "text/plain");
    });
    http_.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_header("X-Content-Type-Options", "nosniff");
      res.set_header("Content-Security-Policy", "default-src 'self'; script-src 'unsafe-inline'; style-src 'unsafe-inline'");
      const std::string_view page = live_page_html();
      res.set_content(page.data(), page.size(), "text/html; charset=utf-8");
    });
    http_.Get("/events", [this](const httplib::Request&, httplib::Response& res) { open_stream(res); });
    http_.Get("/frame.jpg", [this](const httplib::Request&, httplib::Response& res) {
      const std::string jpeg = camera_.jpeg();
      if (jpeg.empty()) {
        res.status = 404;
        return;
      }
      res.set_header("Cache-Control", "no-store");
      res.set_content(jpeg, "image/jpeg");
    });
    if (!http_.bind_to_port(at.host, at.port))
      throw InputError("--web", 0, "", "cannot listen on " + at.host + ":" + std::to_string(at.port) +
                                           " (in use, or not an address of this machine)");
    port_ = at.port;
    thread_ = std::thread([this] { http_.listen_after_bind(); });
  }

  ~Server() {
    stopping_ = true;
    ring_.close();  // releases every stream's wait
    http_.stop();
    thread_.join();
  }
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const { return port_; }
  const std::string& host() const { return host_; }
  const std::string& token() const { return options_.token; }
  std::uint64_t served() const { return served_.load(); }
  std::uint64_t dropped() const { return dropped_.load(); }

  void on_frame(const FrameSample& frame, const std::vector<LedObservation>& leds) {
    if (camera_.offer(frame, leds))
      ring_.push(sse("frame", "{\"n\":" + std::to_string(camera_.number()) + ",\"w\":" + std::to_string(frame.gray.cols) +
                                  ",\"h\":" + std::to_string(frame.gray.rows) + "}"));
  }

  void on_cloud(const std::vector<Eigen::Vector2d>& particles) {
    std::string pts = "{\"p\":[";
    pts.reserve(16 * particles.size() + 16);
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (!std::isfinite(particles[i].x()) || !std::isfinite(particles[i].y())) continue;
      if (pts.back() == ']') pts += ',';
      pts += "[" + format_fixed(particles[i].x(), 2) + "," + format_fixed(particles[i].y(), 2) + "]";
    }
    ring_.push(sse("cloud", pts + "]}"));
  }

  // The output thread: a pose event now and then, a status event once a second.
  void on_pose(const PoseEstimate& p) {
    const auto now = std::chrono::steady_clock::now();
    latency_.add(p.latency_s);
    if (now - last_pose_ >= options_.pose_interval) {
      last_pose_ = now;
      JsonObject o;
      o.add_number("t", format_time_s(p.t, 3));
      o.add_number("x", format_fixed(p.p_BinW.x(), 3));
      o.add_number("y", format_fixed(p.p_BinW.y(), 3));
      o.add_number("yaw", format_fixed(p.yaw, 3));
      o.add_number("sx", format_fixed(p.sigma_x, 3));
      o.add_number("sy", format_fixed(p.sigma_y, 3));
      o.add_number("leds", std::to_string(p.leds));
      if (!p.mode.empty()) o.add_string("mode", p.mode);
      if (!p.motion.empty()) o.add_string("motion", p.motion);
      o.add_number("latency_ms", format_fixed(1e3 * p.latency_s, 3));
      {
        std::lock_guard lock(trail_mutex_);
        trail_.push_back("[" + format_time_s(p.t, 3) + "," + format_fixed(p.p_BinW.x(), 3) + "," +
                         format_fixed(p.p_BinW.y(), 3) + "]");
        if (trail_.size() > options_.history) trail_.pop_front();
      }
      ring_.push(sse("pose", o.str()));
    }
    if (now - last_status_ >= options_.status_interval) {
      const double dt = std::chrono::duration<double>(now - last_status_).count();
      last_status_ = now;
      JsonObject s, rates, drops;
      for (std::size_t i = 0; i < monitor_.source_names.size(); ++i) {
        if (monitor_.counters && i < monitor_.counters->size()) {
          const std::uint64_t c = monitor_.counters->count(i);
          rates.add_number(monitor_.source_names[i], format_fixed(static_cast<double>(c - last_counts_[i]) / dt, 1));
          last_counts_[i] = c;
        }
        if (i < monitor_.source_drops.size() && monitor_.source_drops[i])
          drops.add_number(monitor_.source_names[i], std::to_string(monitor_.source_drops[i]->total()));
      }
      s.add_object("rates_hz", rates);
      s.add_object("source_drops", drops);
      if (const LatencySummary l = latency_.summary(); l.count > 0) {
        s.add_number("latency_p50_ms", format_fixed(1e3 * l.p50_s, 3));
        s.add_number("latency_p99_ms", format_fixed(1e3 * l.p99_s, 3));
      }
      s.add_number("browsers", std::to_string(streams_.load()));
      s.add_number("browsers_dropped", std::to_string(dropped_.load()));
      ring_.push(sse("status", s.str()));
    }
  }

 private:
  std::string init_json() {
    JsonObject o;
    o.add_string("device", options_.device_id);
    o.add_raw("leds", leds_json_);
    std::string trail = "[";
    {
      std::lock_guard lock(trail_mutex_);
      for (const auto& p : trail_) trail += (trail.size() > 1 ? "," : "") + p;
    }
    o.add_raw("trail", trail + "]");
    return o.str();
  }

  void open_stream(httplib::Response& res) {
    if (streams_.fetch_add(1) >= options_.max_clients) {
      streams_.fetch_sub(1);
      res.status = 503;
      res.set_content("too many browsers watching\n", "text/plain");
      return;
    }
    served_.fetch_add(1);
    struct Stream {
      std::uint64_t from;
      bool started = false;
    };
    auto stream = std::make_shared<Stream>(Stream{ring_.next()});
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, stream](std::size_t, httplib::DataSink& sink) {
          if (stopping_) return false;
          if (!stream->started) {
            stream->started = true;
            const std::string init = "retry: 1000\n\n" + sse("init", init_json());
            return sink.write(init.data(), init.size());
          }
          std::vector<std::string> events;
          if (!ring_.read(stream->from, events, std::chrono::milliseconds(1000))) {
            if (!stopping_) dropped_.fetch_add(1);  // fell a whole ring behind
            return false;
          }
          if (events.empty()) events.push_back(": keep-alive\n\n");
          for (const auto& e : events)
            if (!sink.write(e.data(), e.size())) {  // gone, or stalled past the write timeout
              if (!stopping_) dropped_.fetch_add(1);
              return false;
            }
          return true;
        },
        [this](bool) { streams_.fetch_sub(1); });
  }

  LiveViewOptions options_;
  RunMonitor monitor_;
  EventRing ring_;
  CameraSnapshot camera_;
  std::string host_;
  std::string leds_json_;
  httplib::Server http_;
  std::thread thread_;
  int port_ = 0;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> served_{0}, dropped_{0};
  std::atomic<std::size_t> streams_{0};
  std::mutex trail_mutex_;
  std::deque<std::string> trail_;
  // Output thread only.
  std::chrono::steady_clock::time_point last_pose_{}, last_status_ = std::chrono::steady_clock::now();
  std::vector<std::uint64_t> last_counts_;
  LatencyWindow latency_{1024};
};

LiveViewSink::LiveViewSink(const std::string& spec, LiveViewOptions options, RunMonitor monitor,
                           const std::optional<LedMap>& map)
    : spec_(spec) {
  server_ = std::make_unique<Server>(parse_web_endpoint(spec), std::move(options), std::move(monitor), map);
}

LiveViewSink::~LiveViewSink() = default;

void LiveViewSink::write(const PoseEstimate& pose) { server_->on_pose(pose); }
void LiveViewSink::offer_cloud(const std::vector<Eigen::Vector2d>& particles) { server_->on_cloud(particles); }
void LiveViewSink::offer_frame(const FrameSample& frame, const std::vector<LedObservation>& leds) {
  server_->on_frame(frame, leds);
}
int LiveViewSink::port() const { return server_->port(); }
std::string LiveViewSink::url() const {
  const std::string h = server_->host().find(':') != std::string::npos ? "[" + server_->host() + "]" : server_->host();
  return "http://" + h + ":" + std::to_string(port()) + "/" + (server_->token().empty() ? "" : "?token=" + server_->token());
}
std::uint64_t LiveViewSink::clients_served() const { return server_->served(); }
std::uint64_t LiveViewSink::clients_dropped() const { return server_->dropped(); }

}  // namespace luxloc
