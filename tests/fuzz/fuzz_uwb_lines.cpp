// libFuzzer target: the UWB serial line parsers (plugins/uwb): the DWM1001 `lec`/`lep`
// shell output and TOF+AOA records, chosen by the first byte. Ranges and fixes that come
// out are finite; an AOA is either absent (NaN) or finite.
#include <memory>

#include "plugins/uwb/dwm1001_parser.hpp"
#include "plugins/uwb/tof_aoa_line_parser.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

namespace {

void check(const SensorData& d) {
  if (const auto* u = std::get_if<UwbSample>(&d)) {
    fuzz::expect_finite(u->range_m, "range");
    if (u->aoa_rad == u->aoa_rad) fuzz::expect_finite(u->aoa_rad, "aoa");
  } else if (const auto* f = std::get_if<FixSample>(&d)) {
    fuzz::expect_finite(f->p_inW.x(), "fix x");
    fuzz::expect_finite(f->p_inW.y(), "fix y");
  } else {
    fuzz::fail("a UWB parser produced a sample that is neither a range nor a fix");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  DropCounts drops;
  std::unique_ptr<UwbStreamParser> parser;
  if (data[0] & 1) {
    Dwm1001Options o;
    o.emit_position = true;
    parser = std::make_unique<Dwm1001Parser>(drops, o);
  } else {
    parser = std::make_unique<TofAoaLineParser>(drops);
  }
  std::vector<SensorData> out;
  fuzz::feed_in_reads(data + 1, size - 1, 1 + data[0] % 41, 80, 1'000'000'000, 10'000'000,
                      [&](const std::uint8_t* bytes, std::size_t n, TimeNs t) {
                        const std::size_t before = out.size();
                        parser->feed(bytes, n, t, 86'805.0, out);
                        for (std::size_t i = before; i < out.size(); ++i) check(out[i]);
                      });
  return 0;
}
