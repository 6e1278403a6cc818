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

using namespace luxloc;

namespace {

// Tiny parser for one flat JSON object with numeric values only; throws on anything else
// (a string, null, NaN, nesting, a repeated key).
std::map<std::string, double> parse_flat_json(const std::string& s) {
  auto fail = [&s](const char* why) { throw std::runtime_error(std::string(why) + " in: " + s); };
  std::map<std::string, double> out;
  if (s.size() < 2 || s.front() != '{' || s.back() != '}') fail("not an object");
  std::size_t i = 1;
  while (i < s.size() - 1) {
    if (s[i] != '"') fail("key not quoted");
    const std::size_t end = s.find('"', i + 1);
    if (end == std::string::npos || end + 2 >= s.size() || s[end + 1] != ':') fail("bad key");
    const std::string key = s.substr(i + 1, end - i - 1);
    const std::string rest = s.substr(end + 2);
    if (!(std::isdigit(static_cast<unsigned char>(rest[0])) || rest[0] == '-')) fail("value not a JSON number");
    std::size_t used = 0;
    const double v = std::stod(rest, &used);
    if (!std::isfinite(v)) fail("non-finite number");
    if (!out.emplace(key, v).second) fail("repeated key");
    i = end + 2 + used;
    if (s[i] == ',') ++i;
    else if (i != s.size() - 1) fail("missing ','");
  }
  return out;
}

struct Receiver {
  int fd = -1;
  int port = 0;
  Receiver() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;  // the kernel picks a free port
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t len = sizeof a;
    REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
    port = ntohs(a.sin_port);
  }
  ~Receiver() { ::close(fd); }
  // One datagram, or "" after `timeout_ms`.
  std::string receive(int timeout_ms = 2000) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return {};
    char buf[2048];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  }
};

}  // namespace

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
