#pragma once
// TOF + AOA records on a serial line (SPEC.md `uwb:` "and TOF+AOA records"): what a single
// base station with an antenna array reports, in uwb.csv's column order without the time,
//   <anchor>,<range_m>[,<aoa_rad>]
// one per line, stamped at arrival. '#' lines and a header line (anchor,range_m,...) are
// skipped; anything else that does not parse is dropped and counted.
#include "plugins/uwb/uwb_stream_parser.hpp"

namespace luxloc {

class TofAoaLineParser final : public UwbStreamParser {
 public:
  explicit TofAoaLineParser(DropCounts& drops) : UwbStreamParser(drops) {}

 private:
  void on_line(std::string_view line, TimeNs t, std::vector<SensorData>& out) override;
};

}  // namespace luxloc
