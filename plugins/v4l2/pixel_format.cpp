#include "plugins/v4l2/pixel_format.hpp"

#include <linux/videodev2.h>

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace luxloc {

std::uint32_t pixel_format_fourcc(PixelFormat f) {
  switch (f) {
    case PixelFormat::grey: return V4L2_PIX_FMT_GREY;
    case PixelFormat::yuyv: return V4L2_PIX_FMT_YUYV;
    case PixelFormat::mjpeg: return V4L2_PIX_FMT_MJPEG;
  }
  return 0;
}

std::optional<PixelFormat> pixel_format_from_fourcc(std::uint32_t fourcc) {
  if (fourcc == V4L2_PIX_FMT_GREY) return PixelFormat::grey;
  if (fourcc == V4L2_PIX_FMT_YUYV) return PixelFormat::yuyv;
  if (fourcc == V4L2_PIX_FMT_MJPEG || fourcc == V4L2_PIX_FMT_JPEG) return PixelFormat::mjpeg;
  return std::nullopt;
}

PixelFormat parse_pixel_format(const std::string& name) {
  if (name == "grey" || name == "gray") return PixelFormat::grey;
  if (name == "yuyv") return PixelFormat::yuyv;
  if (name == "mjpeg" || name == "jpeg") return PixelFormat::mjpeg;
  throw std::invalid_argument("format must be grey, yuyv or mjpeg, not '" + name + "'");
}

std::string pixel_format_name(PixelFormat f) {
  switch (f) {
    case PixelFormat::grey: return "grey";
    case PixelFormat::yuyv: return "yuyv";
    case PixelFormat::mjpeg: return "mjpeg";
  }
  return "?";
}

std::string fourcc_text(std::uint32_t fourcc) {
  std::string s(4, '.');
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xff);
    if (c >= 0x20 && c < 0x7f) s[static_cast<std::size_t>(i)] = c;
  }
  return s;
}

namespace {

bool too_short(std::size_t bytes, std::size_t need, std::string& error) {
  if (bytes >= need) return false;
  error = "buffer holds " + std::to_string(bytes) + " bytes, the format needs " + std::to_string(need);
  return true;
}

}  // namespace

bool to_gray8(PixelFormat format, const std::uint8_t* data, std::size_t bytes, const FrameLayout& layout,
              cv::Mat& out, std::string& error) {
  const int w = layout.width, h = layout.height;
  if (w <= 0 || h <= 0 || data == nullptr) {
    error = "empty frame";
    return false;
  }
  switch (format) {
    case PixelFormat::grey: {
      const std::size_t stride = layout.bytes_per_line > 0 ? static_cast<std::size_t>(layout.bytes_per_line)
                                                           : static_cast<std::size_t>(w);
      if (stride < static_cast<std::size_t>(w)) {
        error = "bytes per line " + std::to_string(stride) + " < width " + std::to_string(w);
        return false;
      }
      // The last row need not carry its padding.
      if (too_short(bytes, stride * static_cast<std::size_t>(h - 1) + static_cast<std::size_t>(w), error)) return false;
      // Wrap the driver's rows (with their padding) and copy: the buffer goes back to the driver.
      cv::Mat(h, w, CV_8UC1, const_cast<std::uint8_t*>(data), stride).copyTo(out);
      return true;
    }
    case PixelFormat::yuyv: {
      // Packed 4:2:2, Y0 U Y1 V: the luma is every even byte.
      const std::size_t packed = 2 * static_cast<std::size_t>(w);
      const std::size_t stride = layout.bytes_per_line > 0 ? static_cast<std::size_t>(layout.bytes_per_line) : packed;
      if (stride < packed) {
        error = "bytes per line " + std::to_string(stride) + " < 2 x width " + std::to_string(w);
        return false;
      }
      if (too_short(bytes, stride * static_cast<std::size_t>(h - 1) + packed, error)) return false;
      out.create(h, w, CV_8UC1);
      for (int r = 0; r < h; ++r) {
        const std::uint8_t* src = data + stride * static_cast<std::size_t>(r);
        std::uint8_t* dst = out.ptr<std::uint8_t>(r);
        for (int c = 0; c < w; ++c) dst[c] = src[2 * c];
      }
      return true;
    }
    case PixelFormat::mjpeg: {
      if (bytes < 4) {
        error = "empty JPEG buffer";
        return false;
      }
      const cv::Mat encoded(1, static_cast<int>(bytes), CV_8UC1, const_cast<std::uint8_t*>(data));
      cv::Mat decoded;
      try {
        decoded = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
      } catch (const cv::Exception& e) {
        error = std::string("JPEG does not decode: ") + e.what();
        return false;
      }
      if (decoded.empty()) {
        error = "JPEG does not decode (" + std::to_string(bytes) + " bytes)";
        return false;
      }
      if (decoded.cols != w || decoded.rows != h) {
        error = "JPEG is " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) + ", expected " +
                std::to_string(w) + "x" + std::to_string(h);
        return false;
      }
      out = decoded;
      return true;
    }
  }
  error = "unknown format";
  return false;
}

}  // namespace luxloc
