// libFuzzer target: the text-line serial IMU parser (plugins/serial/csv_line_parser), in
// both time modes (arrival, device clock) chosen by the first byte. Samples out are finite.

#include "plugins/serial/csv_line_parser.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  CsvLineOptions options;
  options.device_time = data[0] & 1;
  options.max_line = 128;
  DropCounts drops;
  CsvLineParser parser(drops, options);
  std::vector<ImuSample> out;
  fuzz::feed_in_reads(data + 1, size - 1, 1 + data[0] % 29, 50, 5'000'000'000, 2'000'000,
                      [&](const std::uint8_t* bytes, std::size_t n, TimeNs t) {
                        const std::size_t before = out.size();
                        parser.feed(bytes, n, t, 86'805.0, out);
                        for (std::size_t i = before; i < out.size(); ++i) {
                          for (int k = 0; k < 3; ++k) {
                            fuzz::expect_finite(out[i].acc_inB[k], "acc");
                            fuzz::expect_finite(out[i].gyro_inB[k], "gyro");
                            if (out[i].has_mag) fuzz::expect_finite(out[i].mag_inB[k], "mag");
                          }
                        }
                      });
  return 0;
}
