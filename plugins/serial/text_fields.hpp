#pragma once
// Fields of one text line from a serial device (CSV IMU lines, DWM1001 / TOF+AOA UWB lines).
#include <string_view>
#include <vector>

namespace luxloc {

// Splits on any character of `delimiters`, keeping empty fields; trims spaces and tabs.
std::vector<std::string_view> split_trimmed(std::string_view line, std::string_view delimiters);
// A whole field as a finite number ("+1.5", "-0.25"); false for "", "nan", "inf", garbage.
bool parse_finite_number(std::string_view s, double& v);

}  // namespace luxloc
