// JSON-over-UDP output: real sockets on the loopback, datagrams parsed back.
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "core/common/input_error.hpp"
#include "plugins/output/udp_pose_sink.hpp"
#include "plugins/output/udp_receiver.hpp"

using namespace luxloc;
using luxloc::test::parse_flat_json;
using luxloc::test::Receiver;


TEST_CASE("UDP sink: N poses -> N flat JSON datagrams in seq order", "[io]") {
  Receiver rx;
  UdpPoseSink sink("127.0.0.1:" + std::to_string(rx.port));
  const int n = 50;
  for (int i = 0; i < n; ++i) {
    PoseEstimate p;
    p.t = 1'000'000'000LL + i * 10'000'000LL;
    p.p_BinW = {0.1 * i, -0.2 * i, 1.0};
    p.yaw = 0.01 * i;
    if (i > 0) p.sigma_x = p.sigma_y = 0.05;  // the first pose has no sigma yet: omitted
    p.leds = i % 4;
    sink.write(p);
  }
  sink.flush();
  for (int i = 0; i < n; ++i) {
    const std::string msg = rx.receive();
    REQUIRE_FALSE(msg.empty());
    CHECK(msg.find("nan") == std::string::npos);
    const auto j = parse_flat_json(msg);
    CHECK(j.at("seq") == i);
    CHECK(j.at("t") == Approx(1.0 + 0.01 * i));
    CHECK(j.at("x") == Approx(0.1 * i).margin(1e-5));
    CHECK(j.at("y") == Approx(-0.2 * i).margin(1e-5));
    CHECK(j.at("z") == Approx(1.0));
    CHECK(j.at("yaw") == Approx(0.01 * i).margin(1e-5));
    CHECK(j.at("leds") == i % 4);
    CHECK(j.count("n_eff") == 0);
    if (i == 0) {
      CHECK(j.count("sigma_x") == 0);
    } else {
      CHECK(j.at("sigma_x") == Approx(0.05));
      CHECK(j.at("sigma_y") == Approx(0.05));
    }
  }
  CHECK(sink.sent() == static_cast<std::uint64_t>(n));
  CHECK(sink.drops().total() == 0);
}

TEST_CASE("UDP sink: hostnames and IPv6 literals resolve", "[io]") {
  Receiver rx;
  UdpPoseSink by_name("localhost:" + std::to_string(rx.port));  // IPv4 preferred
  by_name.write(PoseEstimate{});
  CHECK(parse_flat_json(rx.receive()).at("seq") == 0);
  // An IPv6 literal in brackets (loopback may lack IPv6 in containers: construction only).
  try {
    UdpPoseSink v6("[::1]:9");
    CHECK(v6.name() == "udp:[::1]:9");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), Catch::Contains("::1"));
  }
}

TEST_CASE("UDP sink: no receiver is counted, never thrown, never blocks", "[io]") {
  int port = 0;
  {
    Receiver gone;  // take a free port, then close it: nobody listens there
    port = gone.port;
  }
  UdpPoseSink sink("127.0.0.1:" + std::to_string(port));
  const auto start = std::chrono::steady_clock::now();
  CHECK_NOTHROW([&] {
    for (int i = 0; i < 2000; ++i) sink.write(PoseEstimate{});
  }());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(s < 1.0);
  CHECK(sink.next_seq() == 2000);
  CHECK(sink.drops().count("no receiver") > 0);
  CHECK(sink.sent() + sink.drops().total() == 2000);
}

TEST_CASE("UDP sink: malformed HOST:PORT is an InputError with a clear message", "[io]") {
  for (const char* bad : {"localhost", "localhost:", ":9870", "localhost:abc", "localhost:0", "localhost:70000",
                          "::1:9870", "[::1]9870", "[::1:9870"}) {
    INFO(bad);
    CHECK_THROWS_AS(parse_udp_endpoint(bad), InputError);
  }
  CHECK_THROWS_WITH(UdpPoseSink("localhost:x"), Catch::Contains("HOST:PORT"));
  CHECK_THROWS_WITH(UdpPoseSink("no-such-host.invalid:9870"), Catch::Contains("cannot resolve"));
  const UdpEndpoint e = parse_udp_endpoint("[::1]:9870");
  CHECK(e.host == "::1");
  CHECK(e.port == "9870");
  CHECK(parse_udp_endpoint("10.0.0.2:00080").port == "80");
}
