#include "core/pipeline/source_lag.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

void SourceLag::update(TimeNs stamp, TimeNs arrival) {
  const double lag = static_cast<double>(arrival - stamp);
  if (n_ == 0) {
    high_ = max_ = lag;
  } else if (lag >= high_) {
    high_ = lag;
  } else {
    const double dt_s = std::max(0.0, 1e-9 * static_cast<double>(stamp - last_stamp_));
    high_ += (lag - high_) * (1.0 - std::exp(-dt_s / kLagRelaxS));
  }
  max_ = std::max(max_, lag);
  sum_ += lag;
  ++n_;
  last_stamp_ = stamp;
}

}  // namespace luxloc
