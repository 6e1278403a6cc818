#pragma once
// Decawave (Qorvo) DWM1001 tag, UART shell in `lec` mode: one CSV line per location
// update,
//   DIST,<n>,AN0,<id>,<x>,<y>,<z>,<range>,...,AN<n-1>,...,POS,<x>,<y>,<z>,<quality>
// <id> the anchor's 16-bit short address in hex (022E), positions and ranges in metres; the
// POS block (the tag's own solution, quality factor 0..100) is absent when the tag has no
// position. `lep` mode lines (POS,<x>,<y>,<z>,<quality>) are read too.
// Out: one UwbSample per anchor (id = the hex address as an integer, 0x022E -> 558, range
// as the 3-D distance, the anchor position the tag reported in p_AinW) and, with
// emit_position, a FixSample from POS (quality >= min_quality).
// The shell's own output (prompt "dwm>", the echoed command, help text) is ignored; a DIST
// line whose structure is inconsistent (count vs blocks, a field not a number — what the
// tag prints when two reports interleave at high update rates) is dropped whole.
#include "plugins/uwb/uwb_stream_parser.hpp"

namespace luxloc {

struct Dwm1001Options {
  bool emit_ranges = true;
  bool emit_position = false;
  int min_quality = 50;        // POS below this quality factor is not used
  double position_sigma_m = 0.15;  // sigma of a FixSample from POS
};

class Dwm1001Parser final : public UwbStreamParser {
 public:
  Dwm1001Parser(DropCounts& drops, const Dwm1001Options& options = {}) : UwbStreamParser(drops), options_(options) {}
  std::uint64_t records() const { return records_; }

 private:
  void on_line(std::string_view line, TimeNs t, std::vector<SensorData>& out) override;
  bool parse_pos(const std::vector<std::string_view>& f, std::size_t at, TimeNs t, std::vector<SensorData>& out);

  Dwm1001Options options_;
  std::uint64_t records_ = 0;
};

}  // namespace luxloc
