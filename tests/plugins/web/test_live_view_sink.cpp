// The live view's HTTP server, in process: only its own paths, the token, several
// browsers, a stalled browser dropped, and write() never waiting for any of them.
// Eigen (through the LED map) before httplib.h: a resolver header it pulls in defines
// macros that break Eigen's templates.
#include "plugins/web/live_view_sink.hpp"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "core/common/input_error.hpp"
#include "plugins/output/mqtt_broker.hpp"  // free_tcp_port

using namespace luxloc;
using namespace luxloc::test;
using Clock = std::chrono::steady_clock;

namespace {

PoseEstimate pose_at(int k) {
  PoseEstimate p;
  p.t = seconds_to_ns(10.0 + 0.01 * k);
  p.p_BinW = {1.0 + 0.001 * k, 2.0, 1.0};
  p.sigma_x = p.sigma_y = 0.1;
  p.mode = "fused";
  return p;
}

// Reads one event stream until `until` or the end; returns what came.
std::string read_events(httplib::Client& c, const std::string& path, std::chrono::milliseconds for_how_long) {
  std::string got;
  const auto until = Clock::now() + for_how_long;
  c.Get(path.c_str(), [&](const char* data, std::size_t n) {
    got.append(data, n);
    return Clock::now() < until;
  });
  return got;
}

}  // namespace

TEST_CASE("Live view addresses: PORT and :PORT bind 127.0.0.1, HOST:PORT as given", "[plugins][web]") {
  CHECK(parse_web_endpoint("8080").host == "127.0.0.1");
  CHECK(parse_web_endpoint("8080").port == 8080);
  CHECK(parse_web_endpoint(":8081").host == "127.0.0.1");
  CHECK(parse_web_endpoint("0.0.0.0:8082").host == "0.0.0.0");
  CHECK(parse_web_endpoint("[::1]:8083").host == "::1");
  for (const char* bad : {"", "web", "host:", "host:0", "99999", "1.2.3.4:abc"}) {
    INFO(bad);
    CHECK_THROWS_AS(parse_web_endpoint(bad), InputError);
  }
}

TEST_CASE("The live view serves its page and event stream and nothing else", "[plugins][web]") {
  const int port = free_tcp_port();
  LiveViewOptions o;
  o.device_id = "unit";
  o.pose_interval = std::chrono::milliseconds(0);
  LedMap map({Led{7, 2500.0, {1.2, 3.4, 2.9}}}, "test");
  LiveViewSink view(std::to_string(port), o, {}, map);
  CHECK(view.url() == "http://127.0.0.1:" + std::to_string(port) + "/");
  httplib::Client c("127.0.0.1", port);
  const auto page = c.Get("/");
  REQUIRE(page);
  CHECK(page->status == 200);
  CHECK(page->get_header_value("Content-Type").find("text/html") == 0);
  CHECK(page->body.find("EventSource") != std::string::npos);
  for (const char* path : {"/../", "/etc/passwd", "/../../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/index.html",
                           "/events/../../etc/passwd", "/page.js"}) {
    const auto r = c.Get(path);
    INFO(path);
    REQUIRE(r);
    CHECK(r->status == 404);
    CHECK(r->body.find("root:") == std::string::npos);
  }
  CHECK(c.Post("/", "x", "text/plain")->status == 404);  // read-only: no other method
  CHECK(c.Get("/frame.jpg")->status == 404);             // no camera picture yet
  FrameSample frame;
  frame.gray = cv::Mat(120, 160, CV_8UC1, cv::Scalar(40));
  view.offer_frame(frame, {});
  const auto jpeg = c.Get("/frame.jpg");
  REQUIRE(jpeg);
  CHECK(jpeg->status == 200);
  CHECK(jpeg->get_header_value("Content-Type") == "image/jpeg");
  CHECK(jpeg->body.rfind("\xff\xd8", 0) == 0);  // a JPEG's start-of-image marker
  // The stream: init (device, map), then the poses written meanwhile.
  std::thread writer([&] {
    for (int k = 0; k < 50; ++k) {
      if (k == 25) view.offer_cloud({{1.0, 2.0}, {1.5, 2.25}});
      view.write(pose_at(k));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  httplib::Client s("127.0.0.1", port);
  const std::string got = read_events(s, "/events", std::chrono::milliseconds(400));
  writer.join();
  INFO(got);
  CHECK(got.find("event: init\ndata: {\"device\":\"unit\",\"leds\":[{\"id\":7,\"f\":2500.0,\"x\":1.200") != std::string::npos);
  CHECK(got.find("event: pose\ndata: {\"t\":") != std::string::npos);
  CHECK(got.find("event: cloud\ndata: {\"p\":[[1.00,2.00],[1.50,2.25]]}") != std::string::npos);
  CHECK(view.clients_served() == 1);
}

TEST_CASE("With a token the live view answers 403 to every request without it", "[plugins][web]") {
  const int port = free_tcp_port();
  LiveViewOptions o;
  o.token = "s3cret";
  LiveViewSink view("127.0.0.1:" + std::to_string(port), o);
  CHECK(view.url().find("?token=s3cret") != std::string::npos);
  httplib::Client c("127.0.0.1", port);
  for (const char* path : {"/", "/events", "/?token=", "/?token=s3cre", "/?token=s3cret2", "/etc/passwd"}) {
    const auto r = c.Get(path);
    INFO(path);
    REQUIRE(r);
    CHECK(r->status == 403);
    CHECK(r->body.find("EventSource") == std::string::npos);
  }
  CHECK(c.Get("/?token=s3cret")->status == 200);
  CHECK(c.Get("/etc/passwd?token=s3cret")->status == 404);
}

TEST_CASE("A stalled browser is dropped, the others go on, and write() never waits", "[plugins][web]") {
  const int port = free_tcp_port();
  LiveViewOptions o;
  o.pose_interval = std::chrono::milliseconds(0);  // every pose: a lot to send
  o.ring_capacity = 256;
  o.write_timeout = std::chrono::seconds(1);
  o.max_clients = 3;
  LiveViewSink view(std::to_string(port), o);
  // The stalled one: asks for the stream with a tiny receive buffer and never reads.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  const int small = 1024;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  const std::string req = "GET /events HTTP/1.1\r\nHost: x\r\n\r\n";
  REQUIRE(::send(fd, req.data(), req.size(), 0) == static_cast<ssize_t>(req.size()));
  for (int i = 0; i < 100 && view.clients_served() < 1; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(view.clients_served() == 1);
  // A healthy browser reads along.
  std::string healthy;
  std::atomic<bool> reading{true};
  std::thread reader([&] {
    httplib::Client c("127.0.0.1", port);
    healthy = read_events(c, "/events", std::chrono::milliseconds(2500));
    reading = false;
  });
  // ~5000 poses a second (1 MB/s of events) until the stalled one is dropped and the
  // healthy one has read for 2.5 s.
  double slowest_ms = 0.0;
  const auto until = Clock::now() + std::chrono::seconds(8);
  int k = 0;
  while ((reading || view.clients_dropped() < 1) && Clock::now() < until) {
    const auto t0 = Clock::now();
    view.write(pose_at(k++));
    slowest_ms = std::max(slowest_ms, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (k % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  reader.join();
  ::close(fd);
  INFO(k << " poses written, slowest write " << slowest_ms << " ms");
  CHECK(view.clients_dropped() >= 1);
  CHECK(slowest_ms < 50.0);
  CHECK(healthy.find("event: pose") != std::string::npos);
  // Streams beyond max_clients are refused, not queued.
  std::vector<std::thread> watchers;
  for (int i = 0; i < 3; ++i)
    watchers.emplace_back([&] {
      httplib::Client c("127.0.0.1", port);
      read_events(c, "/events", std::chrono::milliseconds(1500));
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  httplib::Client extra("127.0.0.1", port);
  const auto r = extra.Get("/events");
  for (auto& w : watchers) w.join();
  REQUIRE(r);
  CHECK(r->status == 503);
}
