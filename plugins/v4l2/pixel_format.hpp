#pragma once
// Camera pixel formats the V4L2 source accepts and their conversion to the 8-bit gray
// frame the stripe decoder reads (FrameSample::gray, sensor orientation, rows = readout
// order). Only the luma matters for stripes: GREY is taken as is, YUYV keeps its Y bytes,
// MJPEG is decoded straight to gray (cv::imdecode, IMREAD_GRAYSCALE: no colour work).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core/mat.hpp>

namespace luxloc {

enum class PixelFormat { grey, yuyv, mjpeg };

// V4L2 fourcc of the format (V4L2_PIX_FMT_GREY / YUYV / MJPEG).
std::uint32_t pixel_format_fourcc(PixelFormat f);
// Inverse; JPEG ('JPEG', sent by some cameras for the same stream) counts as mjpeg.
std::optional<PixelFormat> pixel_format_from_fourcc(std::uint32_t fourcc);
// "grey" (or "gray"), "yuyv", "mjpeg" (or "jpeg"); throws std::invalid_argument otherwise.
PixelFormat parse_pixel_format(const std::string& name);
std::string pixel_format_name(PixelFormat f);
// 'YUYV' -> "YUYV" (non-printable bytes as '.').
std::string fourcc_text(std::uint32_t fourcc);

struct FrameLayout {
  int width = 0;
  int height = 0;
  int bytes_per_line = 0;  // 0: packed (width x bytes per pixel); ignored for MJPEG
};

// Converts one driver buffer (`bytes` = bytesused) to CV_8UC1 `out` of width x height.
// Returns false with `error` set when the buffer is too short, the JPEG does not decode or
// decodes to another size; `out` then holds nothing valid. `out` never aliases `data`.
bool to_gray8(PixelFormat format, const std::uint8_t* data, std::size_t bytes, const FrameLayout& layout,
              cv::Mat& out, std::string& error);

}  // namespace luxloc
