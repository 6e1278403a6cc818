#pragma once
// JSON-over-UDP pose output (SPEC.md "Pose output", `--udp HOST:PORT`, repeatable: one sink
// per target). One flat JSON object per datagram, numeric fields only:
//   {"t":12.345678,"x":1.23456,"y":..,"z":..,"yaw":..,"sigma_x":..,"sigma_y":..,
//    "sigma_yaw":..,"sigma_z":..,"roll":..,"pitch":..,"n_eff":..,"leds":3,"seq":41}
// the shape PlotJuggler's UDP/JSON server takes as is. A value that is unknown (NaN, e.g.
// sigma before the filter has one, n_eff of a non-particle filter) is OMITTED, never
// written as NaN or null. seq counts every pose handed to write() from 0, so a receiver
// can see losses. Units as in the CSV output (s, m, rad).
//
// Sending never blocks and never fails the run: the socket is non-blocking (MSG_DONTWAIT);
// an absent receiver (ECONNREFUSED), a full buffer (EAGAIN/ENOBUFS) or another send error
// is counted in drops() ("no receiver", "buffer full", "send error").
#include <cstdint>
#include <string>

#include "core/pipeline/pose_sink.hpp"

namespace luxloc {

struct UdpEndpoint {
  std::string host;  // name, IPv4 literal, or IPv6 literal (without brackets)
  std::string port;  // decimal, 1..65535
};

// "HOST:PORT", "[IPV6]:PORT"; throws InputError (exit 2) with a clear message otherwise.
UdpEndpoint parse_udp_endpoint(const std::string& spec);

// The datagram body for one pose.
std::string pose_json(const PoseEstimate& pose, std::uint64_t seq);

class UdpPoseSink : public PoseSink {
 public:
  // Resolves HOST with getaddrinfo (IPv4 and IPv6; a name with both kinds of address uses
  // IPv4, as UDP plot servers usually listen on 0.0.0.0) and opens a connected,
  // non-blocking datagram socket. Throws InputError for a malformed spec or unknown host.
  explicit UdpPoseSink(const std::string& host_port);
  ~UdpPoseSink() override;
  UdpPoseSink(const UdpPoseSink&) = delete;
  UdpPoseSink& operator=(const UdpPoseSink&) = delete;

  std::string name() const override { return "udp:" + spec_; }
  void write(const PoseEstimate& pose) override;
  std::uint64_t sent() const { return sent_; }      // datagrams accepted by the kernel
  std::uint64_t next_seq() const { return seq_; }

 private:
  std::string spec_;
  int fd_ = -1;
  std::uint64_t seq_ = 0;
  std::uint64_t sent_ = 0;
};

}  // namespace luxloc
