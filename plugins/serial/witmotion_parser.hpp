#pragma once
// WitMotion WT901-family binary protocol ("standard protocol"): 11-byte packets
//   0x55, type, 8 data bytes (four little-endian int16), checksum
// where checksum = low byte of the sum of the first ten bytes. Types used here:
//   0x51 acceleration   a = raw / 32768 * acc_range_g (16 g) * 9.80665 m/s^2, 4th word: temperature / 100 C
//   0x52 angular rate   w = raw / 32768 * gyro_range_dps (2000 deg/s), to rad/s
//   0x53 angles         roll, pitch, yaw = raw / 32768 * 180 deg (the device's own fusion; kept for reference)
//   0x54 magnetic field raw counts * mag_scale_ut. WitMotion documents no unit for this
//                       packet (it depends on the magnetometer chip), so the default scale
//                       is 1 (counts); luxloc's attitude filter uses the field's direction
//                       and its relative magnitude only, so counts work as they are.
// Other types 0x50..0x5A (time, quaternion, GPS...) are valid packets that are skipped.
//
// A device sends a fixed cycle of packets per output period, in ascending type order (e.g.
// 51 52 53 54). A type not above the previous one starts a new cycle; the parser learns the
// cycle's last type from the first such boundary and then emits one ImuSample as soon as that
// type arrives (stamped at its last byte). A cycle missing acc or gyro (a packet lost to a
// bad checksum) is counted as an incomplete sample.
//
// Resynchronisation: bytes are skipped one at a time until a 0x55 starts a packet of a
// known type with a valid checksum. Right after skipped bytes a candidate is only accepted
// when no 0x55 inside it starts a valid packet too (garbage ending in 0x55 could otherwise
// pass the checksum by chance, 1 in 256, and swallow the real packet's header).
#include <array>

#include "plugins/serial/imu_stream_parser.hpp"

namespace luxloc {

struct WitMotionOptions {
  double acc_range_g = 16.0;
  double gyro_range_dps = 2000.0;
  double mag_scale_ut = 1.0;  // microtesla per count
};

class WitMotionParser final : public ImuStreamParser {
 public:
  WitMotionParser(DropCounts& drops, const WitMotionOptions& options = {});
  void feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
            std::vector<ImuSample>& out) override;
  void reset() override;

  std::uint64_t packets() const { return packets_; }
  // Last 0x53 angles (deg: roll, pitch, yaw) and 0x51 temperature (C).
  const Eigen::Vector3d& device_angles_deg() const { return angles_deg_; }
  double temperature_c() const { return temperature_c_; }

  // Builds one packet (for tests and simulators): type and four int16 words.
  static std::array<std::uint8_t, 11> encode(std::uint8_t type, const std::array<std::int16_t, 4>& words);

 private:
  static bool valid_at(const std::vector<std::uint8_t>& b, std::size_t i);
  void on_packet(const std::uint8_t* p, TimeNs t, std::vector<ImuSample>& out);
  void emit(std::vector<ImuSample>& out);

  WitMotionOptions options_;
  std::vector<std::uint8_t> buf_;
  std::vector<TimeNs> buf_t_;  // arrival time of each buffered byte
  bool synced_ = false;
  std::uint64_t packets_ = 0;
  // The cycle being assembled.
  std::uint32_t seen_types_ = 0;  // bit (type - 0x50)
  int last_type_ = -1, cycle_end_type_ = -1;
  bool first_cycle_ = true;
  ImuSample pending_;
  bool have_acc_ = false, have_gyro_ = false;
  TimeNs pending_t_ = 0;
  Eigen::Vector3d angles_deg_ = Eigen::Vector3d::Zero();
  double temperature_c_ = 0.0;
};

}  // namespace luxloc
