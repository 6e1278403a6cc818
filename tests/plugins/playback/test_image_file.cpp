// Frame files: a cut or corrupt PNG/JPEG is refused with a reason before any image library
// sees it (no "libpng error" of its own on stderr), a whole one decodes to gray.
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "plugins/playback/image_file.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

std::vector<std::uint8_t> encoded(const std::string& ext) {
  cv::Mat img(48, 64, CV_8UC3);
  cv::randu(img, cv::Scalar::all(0), cv::Scalar::all(255));  // cv::theRNG: fixed default seed
  std::vector<std::uint8_t> bytes;
  REQUIRE(cv::imencode(ext, img, bytes));
  return bytes;
}

}  // namespace

TEST_CASE("image files: whole PNG and JPEG decode to 8-bit gray", "[io][image]") {
  for (const char* ext : {".png", ".jpg"}) {
    const GrayImage g = decode_gray_image(encoded(ext));
    INFO(ext << ": " << g.error);
    CHECK(g.error.empty());
    REQUIRE(g.gray.type() == CV_8UC1);
    CHECK(g.gray.size() == cv::Size(64, 48));
  }
}

TEST_CASE("image files: cut, bit-flipped or foreign files are refused with a reason", "[io][image]") {
  const auto png = encoded(".png"), jpg = encoded(".jpg");
  for (std::size_t cut : {png.size() / 2, png.size() - 1, std::size_t{20}, std::size_t{9}}) {
    std::vector<std::uint8_t> b(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(cut));
    const GrayImage g = decode_gray_image(b);
    INFO("PNG cut at " << cut << ": " << g.error);
    CHECK(g.gray.empty());
    CHECK_THAT(g.error, Catch::Contains("truncated PNG"));
  }
  std::vector<std::uint8_t> flipped = png;
  flipped[flipped.size() / 2] ^= 0x10;  // inside IDAT
  CHECK_THAT(decode_gray_image(flipped).error, Catch::Contains("CRC mismatch in chunk IDAT"));
  std::vector<std::uint8_t> jcut(jpg.begin(), jpg.begin() + static_cast<std::ptrdiff_t>(jpg.size() / 2));
  CHECK_THAT(decode_gray_image(jcut).error, Catch::Contains("truncated JPEG"));
  CHECK(decode_gray_image(jcut).gray.empty());
  const std::string text = "not an image at all";
  CHECK_THAT(decode_gray_image({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}).error,
             Catch::Contains("not a PNG or JPEG"));
  CHECK_THAT(decode_gray_image({}).error, Catch::Contains("not a PNG or JPEG"));
}

TEST_CASE("image files: read_gray_image names a missing file", "[io][image]") {
  const auto dir = test::scratch_dir("image_file_read");
  CHECK(read_gray_image(dir / "absent.png").error == "file not found");
  const auto png = encoded(".png");
  test::write_text(dir / "ok.png", std::string(png.begin(), png.end()));
  CHECK(read_gray_image(dir / "ok.png").gray.cols == 64);
}
