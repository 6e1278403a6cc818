#include "plugins/serial/witmotion_parser.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace luxloc {
namespace {

constexpr std::uint8_t kHeader = 0x55;
constexpr std::size_t kPacket = 11;
constexpr double kG = 9.80665;

bool known_type(std::uint8_t t) { return t >= 0x50 && t <= 0x5A; }

double word(const std::uint8_t* p, int k) {
  // Data words start after header and type: little-endian int16.
  const auto lo = static_cast<std::uint16_t>(p[2 + 2 * k]);
  const auto hi = static_cast<std::uint16_t>(p[3 + 2 * k]);
  return static_cast<double>(static_cast<std::int16_t>(static_cast<std::uint16_t>(lo | (hi << 8))));
}

}  // namespace

WitMotionParser::WitMotionParser(DropCounts& drops, const WitMotionOptions& options)
    : ImuStreamParser(drops), options_(options) {}

std::array<std::uint8_t, 11> WitMotionParser::encode(std::uint8_t type, const std::array<std::int16_t, 4>& words) {
  std::array<std::uint8_t, 11> p{};
  p[0] = kHeader;
  p[1] = type;
  for (int k = 0; k < 4; ++k) {
    const auto w = static_cast<std::uint16_t>(words[k]);
    p[2 + 2 * k] = static_cast<std::uint8_t>(w & 0xFF);
    p[3 + 2 * k] = static_cast<std::uint8_t>(w >> 8);
  }
  unsigned sum = 0;
  for (int k = 0; k < 10; ++k) sum += p[k];
  p[10] = static_cast<std::uint8_t>(sum & 0xFF);
  return p;
}

void WitMotionParser::reset() {
  buf_.clear();
  buf_t_.clear();
  synced_ = false;
  seen_types_ = 0;
  last_type_ = -1;
  first_cycle_ = true;
  have_acc_ = have_gyro_ = false;
  pending_ = ImuSample{};
}

bool WitMotionParser::valid_at(const std::vector<std::uint8_t>& b, std::size_t i) {
  if (b[i] != kHeader || !known_type(b[i + 1])) return false;
  unsigned sum = 0;
  for (std::size_t k = 0; k < 10; ++k) sum += b[i + k];
  return static_cast<std::uint8_t>(sum & 0xFF) == b[i + 10];
}

void WitMotionParser::feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
                           std::vector<ImuSample>& out) {
  for (std::size_t k = 0; k < size; ++k) {
    buf_.push_back(data[k]);
    buf_t_.push_back(t_end - static_cast<TimeNs>(std::llround(static_cast<double>(size - 1 - k) * byte_ns)));
  }
  std::size_t i = 0, skipped = 0;
  while (i < buf_.size()) {
    if (buf_[i] != kHeader) {
      ++i, ++skipped, synced_ = false;
      continue;
    }
    if (buf_.size() - i < kPacket) break;  // wait for the rest
    if (!valid_at(buf_, i)) {
      if (known_type(buf_[i + 1])) drops_.add(serial_drop::kBadChecksum, "WitMotion packet with a bad checksum");
      ++i, ++skipped, synced_ = false;
      continue;
    }
    if (!synced_) {
      // After garbage: a valid packet starting inside this one means this one is the fake.
      bool wait = false, fake = false;
      for (std::size_t j = i + 1; j < i + kPacket && !fake; ++j) {
        if (buf_[j] != kHeader) continue;
        if (buf_.size() - j < kPacket) {
          wait = true;
          break;
        }
        fake = valid_at(buf_, j);
      }
      if (wait) break;
      if (fake) {
        ++i, ++skipped;
        continue;
      }
    }
    on_packet(&buf_[i], buf_t_[i + kPacket - 1], out);
    i += kPacket;
    synced_ = true;
  }
  if (skipped > 0) drops_.add(serial_drop::kSkippedBytes, "bytes outside valid WitMotion packets", skipped);
  buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(i));
  buf_t_.erase(buf_t_.begin(), buf_t_.begin() + static_cast<std::ptrdiff_t>(i));
}

void WitMotionParser::emit(std::vector<ImuSample>& out) {
  if (seen_types_ != 0) {
    if (have_acc_ && have_gyro_) {
      pending_.t = pending_t_;
      out.push_back(pending_);
    } else if (!first_cycle_) {  // the first cycle may have started half-way through
      drops_.add(serial_drop::kIncompleteSample, "a WitMotion packet cycle without acceleration or angular rate");
    }
    first_cycle_ = false;
  }
  seen_types_ = 0;
  have_acc_ = have_gyro_ = false;
  pending_ = ImuSample{};
}

void WitMotionParser::on_packet(const std::uint8_t* p, TimeNs t, std::vector<ImuSample>& out) {
  ++packets_;
  const int type = p[1];
  const std::uint32_t bit = 1u << (type - 0x50);
  // The device sends its packets in ascending type order: a type not above the previous
  // one starts the next cycle, and the previous type is (at least) the cycle's last.
  if (last_type_ >= 0 && type <= last_type_) {
    cycle_end_type_ = std::max(cycle_end_type_, last_type_);
    emit(out);
  }
  seen_types_ |= bit;
  last_type_ = type;
  pending_t_ = t;
  switch (type) {
    case 0x51: {
      const double k = options_.acc_range_g * kG / 32768.0;
      pending_.acc_inB = {word(p, 0) * k, word(p, 1) * k, word(p, 2) * k};
      temperature_c_ = word(p, 3) / 100.0;
      have_acc_ = true;
      break;
    }
    case 0x52: {
      const double k = options_.gyro_range_dps / 32768.0 * std::numbers::pi / 180.0;
      pending_.gyro_inB = {word(p, 0) * k, word(p, 1) * k, word(p, 2) * k};
      have_gyro_ = true;
      break;
    }
    case 0x53:
      angles_deg_ = {word(p, 0) * 180.0 / 32768.0, word(p, 1) * 180.0 / 32768.0, word(p, 2) * 180.0 / 32768.0};
      break;
    case 0x54:
      pending_.mag_inB = {word(p, 0) * options_.mag_scale_ut, word(p, 1) * options_.mag_scale_ut,
                          word(p, 2) * options_.mag_scale_ut};
      pending_.has_mag = true;
      break;
    default:
      break;
  }
  if (type == cycle_end_type_) emit(out);
}

}  // namespace luxloc
