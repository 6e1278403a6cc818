#pragma once
// Number formatting shared by the pose outputs. Time is printed from the integer ns
// timeline (exact, no double rounding at large epochs); a non-finite value is never
// printed: callers get an empty string and decide (empty CSV field, omitted JSON key).
#include <string>

#include "core/common/time.hpp"

namespace luxloc {

// Seconds with `decimals` (0..9) digits, rounded half away from zero: 1234567890 ns, 6 -> "1.234568".
std::string format_time_s(TimeNs t, int decimals = 6);
// printf("%.*f"); "" when v is NaN or infinite.
std::string format_fixed(double v, int decimals);

}  // namespace luxloc
