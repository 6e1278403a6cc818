#include "plugins/uwb/uwb_stream_parser.hpp"

#include <cmath>

namespace luxloc {

void UwbStreamParser::feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
                           std::vector<SensorData>& out) {
  for (std::size_t k = 0; k < size; ++k) {
    const char c = static_cast<char>(data[k]);
    if (c == '\n') {
      if (!discarding_) {
        std::string_view l = line_;
        while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
        while (!l.empty() && (l.front() == ' ' || l.front() == '\t' || l.front() == '\0' || l.front() == '\r'))
          l.remove_prefix(1);
        if (!l.empty()) {
          ++lines_;
          const TimeNs t = t_end - static_cast<TimeNs>(std::llround(static_cast<double>(size - 1 - k) * byte_ns));
          on_line(l, t, out);
        }
      }
      line_.clear();
      discarding_ = false;
      continue;
    }
    if (discarding_) continue;
    if (line_.size() >= max_line_) {
      drops_.add(uwb_drop::kLongLine, "a line longer than " + std::to_string(max_line_) + " bytes");
      line_.clear();
      discarding_ = true;
      continue;
    }
    line_.push_back(c);
  }
}

}  // namespace luxloc
