// libFuzzer target: the WitMotion binary stream parser (plugins/serial/witmotion_parser).
// The input is cut into reads of varying size (as a serial port delivers it); every sample
// that comes out must be finite and stamped no later than the read that completed it.

#include "plugins/serial/witmotion_parser.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace luxloc;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DropCounts drops;
  WitMotionParser parser(drops);
  std::vector<ImuSample> out;
  fuzz::feed_in_reads(data, size, size ? 1 + data[0] % 37 : 1, 64, 1'000'000'000, 1'000'000,
                      [&](const std::uint8_t* bytes, std::size_t n, TimeNs t) {
                        const std::size_t before = out.size();
                        parser.feed(bytes, n, t, 86'805.0 /* 115200 baud */, out);
                        for (std::size_t i = before; i < out.size(); ++i) {
                          const ImuSample& s = out[i];
                          if (s.t > t) fuzz::fail("sample stamped after its read");
                          for (int k = 0; k < 3; ++k) {
                            fuzz::expect_finite(s.acc_inB[k], "acc");
                            fuzz::expect_finite(s.gyro_inB[k], "gyro");
                            if (s.has_mag) fuzz::expect_finite(s.mag_inB[k], "mag");
                          }
                        }
                      });
  return 0;
}
