// libFuzzer target: the frame decoder (plugins/playback/image_file): any bytes give either
// an 8-bit gray image or a reason, never an exception or a crash in the image libraries.
#include "plugins/playback/image_file.hpp"
#include "tests/fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const luxloc::GrayImage img = luxloc::decode_gray_image({data, size});
  if (img.gray.empty() == img.error.empty()) luxloc::fuzz::fail("an image and an error, or neither");
  if (!img.gray.empty() && img.gray.type() != CV_8UC1) luxloc::fuzz::fail("decoded image is not 8-bit gray");
  return 0;
}
