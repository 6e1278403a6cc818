#pragma once
// Test helpers for the JSON-over-UDP output: a loopback receiver on a kernel-chosen port and
// a strict parser for one flat JSON object of numbers.
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <netinet/in.h>
#include <poll.h>
#include <stdexcept>
#include <string>
#include <sys/socket.h>
#include <unistd.h>

namespace luxloc::test {

// Tiny parser for one flat JSON object with numeric values only; throws on anything else
// (a string, null, NaN, nesting, a repeated key).
inline std::map<std::string, double> parse_flat_json(const std::string& s) {
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


}  // namespace luxloc::test
