// Pixel-format conversions of the V4L2 source on real byte buffers: YUYV luma, GREY with
// row padding, MJPEG through a real JPEG encoder.
#include <catch2/catch.hpp>
#include <cstdint>
#include <linux/videodev2.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "plugins/v4l2/pixel_format.hpp"

using namespace luxloc;

TEST_CASE("YUYV packed 4:2:2 -> the Y plane, with and without row padding", "[v4l2]") {
  const int w = 4, h = 2;
  // Y0 U Y1 V per pixel pair; chroma bytes 200+ must not leak into the luma.
  std::vector<std::uint8_t> buf;
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; c += 2) {
      buf.push_back(static_cast<std::uint8_t>(10 * r + c));
      buf.push_back(200);
      buf.push_back(static_cast<std::uint8_t>(10 * r + c + 1));
      buf.push_back(250);
    }
  cv::Mat g;
  std::string err;
  REQUIRE(to_gray8(PixelFormat::yuyv, buf.data(), buf.size(), {w, h, 0}, g, err));
  REQUIRE(g.type() == CV_8UC1);
  REQUIRE(g.size() == cv::Size(w, h));
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) CHECK(g.at<std::uint8_t>(r, c) == 10 * r + c);

  // 12 bytes per line: 4 bytes of padding after each row's 8.
  std::vector<std::uint8_t> padded;
  for (int r = 0; r < h; ++r) {
    padded.insert(padded.end(), buf.begin() + 8 * r, buf.begin() + 8 * (r + 1));
    padded.insert(padded.end(), {99, 99, 99, 99});
  }
  REQUIRE(to_gray8(PixelFormat::yuyv, padded.data(), padded.size(), {w, h, 12}, g, err));
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) CHECK(g.at<std::uint8_t>(r, c) == 10 * r + c);

  CHECK_FALSE(to_gray8(PixelFormat::yuyv, buf.data(), buf.size() - 1, {w, h, 0}, g, err));
  CHECK_THAT(err, Catch::Contains("15 bytes") && Catch::Contains("16"));
  CHECK_FALSE(to_gray8(PixelFormat::yuyv, buf.data(), buf.size(), {w, h, 6}, g, err));
  CHECK_THAT(err, Catch::Contains("bytes per line"));
}

TEST_CASE("GREY with bytesperline padding: rows copied, padding dropped, buffer not aliased", "[v4l2]") {
  const int w = 5, h = 3, stride = 8;
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(stride * h), 77);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) buf[static_cast<std::size_t>(r * stride + c)] = static_cast<std::uint8_t>(r * 16 + c);
  cv::Mat g;
  std::string err;
  REQUIRE(to_gray8(PixelFormat::grey, buf.data(), buf.size(), {w, h, stride}, g, err));
  REQUIRE(g.size() == cv::Size(w, h));
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) CHECK(g.at<std::uint8_t>(r, c) == r * 16 + c);
  buf[0] = 255;  // the driver reuses its buffer: the frame must not change
  CHECK(g.at<std::uint8_t>(0, 0) == 0);
  // The last row may come without its padding; one byte less is too short.
  CHECK(to_gray8(PixelFormat::grey, buf.data(), static_cast<std::size_t>(stride * (h - 1) + w), {w, h, stride}, g, err));
  CHECK_FALSE(to_gray8(PixelFormat::grey, buf.data(), static_cast<std::size_t>(stride * (h - 1) + w - 1),
                       {w, h, stride}, g, err));
  CHECK_FALSE(to_gray8(PixelFormat::grey, buf.data(), buf.size(), {w, h, 4}, g, err));
}

TEST_CASE("MJPEG: a cv::imencode'd stripe frame decodes to gray within JPEG tolerance", "[v4l2]") {
  // A rolling-shutter-like frame: dark background, a striped disc.
  cv::Mat1b src(120, 160, std::uint8_t{6});
  for (int r = 0; r < src.rows; ++r)
    for (int c = 0; c < src.cols; ++c) {
      const double dr = r - 60.0, dc = c - 80.0;
      if (dr * dr + dc * dc < 40.0 * 40.0) src(r, c) = ((r / 6) % 2) ? 230 : 40;
    }
  std::vector<std::uint8_t> jpeg;
  REQUIRE(cv::imencode(".jpg", src, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  cv::Mat g;
  std::string err;
  REQUIRE(to_gray8(PixelFormat::mjpeg, jpeg.data(), jpeg.size(), {160, 120, 0}, g, err));
  REQUIRE(g.type() == CV_8UC1);
  cv::Mat diff;
  cv::absdiff(g, src, diff);
  double max_diff = 0;
  cv::minMaxLoc(diff, nullptr, &max_diff);
  CHECK(cv::mean(diff)[0] < 2.0);
  CHECK(max_diff < 40.0);  // ringing at the stripe edges only

  // A colour JPEG (what webcams send) decodes to its luma.
  cv::Mat colour;
  cv::cvtColor(src, colour, cv::COLOR_GRAY2BGR);
  REQUIRE(cv::imencode(".jpg", colour, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  REQUIRE(to_gray8(PixelFormat::mjpeg, jpeg.data(), jpeg.size(), {160, 120, 0}, g, err));
  cv::absdiff(g, src, diff);
  CHECK(cv::mean(diff)[0] < 2.5);

  // Wrong size, truncated and garbage buffers are errors, not crashes.
  CHECK_FALSE(to_gray8(PixelFormat::mjpeg, jpeg.data(), jpeg.size(), {320, 240, 0}, g, err));
  CHECK_THAT(err, Catch::Contains("160x120") && Catch::Contains("320x240"));
  std::vector<std::uint8_t> garbage(500, 0x5a);
  CHECK_FALSE(to_gray8(PixelFormat::mjpeg, garbage.data(), garbage.size(), {160, 120, 0}, g, err));
  CHECK_THAT(err, Catch::Contains("JPEG"));
  CHECK_FALSE(to_gray8(PixelFormat::mjpeg, jpeg.data(), 2, {160, 120, 0}, g, err));
}

TEST_CASE("pixel format names and fourccs", "[v4l2]") {
  CHECK(parse_pixel_format("grey") == PixelFormat::grey);
  CHECK(parse_pixel_format("gray") == PixelFormat::grey);
  CHECK(parse_pixel_format("yuyv") == PixelFormat::yuyv);
  CHECK(parse_pixel_format("mjpeg") == PixelFormat::mjpeg);
  CHECK_THROWS_WITH(parse_pixel_format("rgb24"), Catch::Contains("grey, yuyv or mjpeg"));
  CHECK(fourcc_text(pixel_format_fourcc(PixelFormat::yuyv)) == "YUYV");
  CHECK(fourcc_text(pixel_format_fourcc(PixelFormat::mjpeg)) == "MJPG");
  CHECK(pixel_format_from_fourcc(V4L2_PIX_FMT_JPEG) == PixelFormat::mjpeg);
  CHECK_FALSE(pixel_format_from_fourcc(V4L2_PIX_FMT_RGB24).has_value());
}
