#include "plugins/output/udp_pose_sink.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <netdb.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <unistd.h>

#include "core/common/input_error.hpp"
#include "plugins/output/pose_text.hpp"

namespace luxloc {
namespace {

InputError bad_spec(const std::string& spec, const std::string& why) {
  return InputError("--udp", 0, "", "'" + spec + "': " + why + " (expected HOST:PORT, e.g. 127.0.0.1:9870, "
                                                               "localhost:9870 or [::1]:9870)");
}

void append_number(std::string& s, const char* key, const std::string& value) {
  if (value.empty()) return;  // unknown: omitted, never NaN
  if (s.size() > 1) s += ',';
  s += '"';
  s += key;
  s += "\":";
  s += value;
}

}  // namespace

UdpEndpoint parse_udp_endpoint(const std::string& spec) {
  UdpEndpoint e;
  std::string port;
  if (!spec.empty() && spec.front() == '[') {
    const auto close = spec.find(']');
    if (close == std::string::npos) throw bad_spec(spec, "missing ']' after the IPv6 address");
    e.host = spec.substr(1, close - 1);
    if (close + 1 >= spec.size() || spec[close + 1] != ':') throw bad_spec(spec, "missing ':PORT'");
    port = spec.substr(close + 2);
  } else {
    const auto colon = spec.rfind(':');
    if (colon == std::string::npos) throw bad_spec(spec, "missing ':PORT'");
    e.host = spec.substr(0, colon);
    port = spec.substr(colon + 1);
    if (e.host.find(':') != std::string::npos) throw bad_spec(spec, "an IPv6 address must be in brackets");
  }
  if (e.host.empty()) throw bad_spec(spec, "empty host");
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    throw bad_spec(spec, "port '" + port + "' is not a number");
  const int p = std::stoi(port);
  if (p < 1 || p > 65535) throw bad_spec(spec, "port " + port + " out of range 1..65535");
  e.port = std::to_string(p);
  return e;
}

std::string pose_json(const PoseEstimate& p, std::uint64_t seq) {
  std::string s = "{";
  s.reserve(224);
  append_number(s, "t", format_time_s(p.t, 6));
  append_number(s, "x", format_fixed(p.p_BinW.x(), 5));
  append_number(s, "y", format_fixed(p.p_BinW.y(), 5));
  append_number(s, "z", format_fixed(p.p_BinW.z(), 5));
  append_number(s, "yaw", format_fixed(p.yaw, 5));
  append_number(s, "sigma_x", format_fixed(p.sigma_x, 5));
  append_number(s, "sigma_y", format_fixed(p.sigma_y, 5));
  append_number(s, "sigma_yaw", format_fixed(p.sigma_yaw, 5));
  append_number(s, "sigma_z", format_fixed(p.sigma_z, 5));
  append_number(s, "roll", format_fixed(p.roll, 5));
  append_number(s, "pitch", format_fixed(p.pitch, 5));
  append_number(s, "n_eff", format_fixed(p.n_eff, 1));
  append_number(s, "leds", std::to_string(p.leds));
  append_number(s, "seq", std::to_string(seq));
  s += '}';
  return s;
}

UdpPoseSink::UdpPoseSink(const std::string& host_port) : spec_(host_port) {
  const UdpEndpoint e = parse_udp_endpoint(host_port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (const int rc = getaddrinfo(e.host.c_str(), e.port.c_str(), &hints, &found); rc != 0)
    throw InputError("--udp", 0, "", "'" + host_port + "': cannot resolve host '" + e.host + "': " + gai_strerror(rc));
  std::string last_error = "no address";
  // IPv4 first, then IPv6.
  for (int family : {AF_INET, AF_INET6}) {
    for (addrinfo* a = found; a && fd_ < 0; a = a->ai_next) {
      if (a->ai_family != family) continue;
      const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
      if (fd < 0) {
        last_error = std::strerror(errno);
        continue;
      }
      // A connected datagram socket learns of an absent receiver (ICMP port unreachable)
      // as ECONNREFUSED on a later send, which is what we count.
      if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
        last_error = std::strerror(errno);
        ::close(fd);
        continue;
      }
      fd_ = fd;
    }
  }
  freeaddrinfo(found);
  if (fd_ < 0) throw InputError("--udp", 0, "", "'" + host_port + "': cannot open a UDP socket: " + last_error);
}

UdpPoseSink::~UdpPoseSink() {
  if (fd_ >= 0) ::close(fd_);
}

void UdpPoseSink::write(const PoseEstimate& pose) {
  const std::string msg = pose_json(pose, seq_++);
  const ssize_t n = ::send(fd_, msg.data(), msg.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  if (n == static_cast<ssize_t>(msg.size())) {
    ++sent_;
    return;
  }
  const int err = n < 0 ? errno : EMSGSIZE;
  if (err == ECONNREFUSED)
    drops().add("no receiver", name() + ": " + std::strerror(err));
  else if (err == EAGAIN || err == EWOULDBLOCK || err == ENOBUFS)
    drops().add("buffer full", name() + ": " + std::strerror(err));
  else
    drops().add("send error", name() + ": " + std::strerror(err));
}

}  // namespace luxloc
