#include "plugins/playback/image_file.hpp"

#include <zlib.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace luxloc {
namespace {

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// PNG (ISO/IEC 15948 section 5): 8-byte signature, then chunks of length (4, big endian),
// type (4), data, CRC-32 over type and data (4), ending with IEND.
std::string png_error(std::span<const std::uint8_t> b) {
  std::size_t at = 8;
  bool first = true;
  while (true) {
    if (b.size() - at < 12) return "truncated PNG: file ends inside a chunk header (no IEND)";
    const std::uint32_t len = be32(&b[at]);
    const std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    if (len > 0x7fffffffu || b.size() - at - 12 < len) return "truncated PNG: chunk " + type + " ends past the end of the file";
    if (first && type != "IHDR") return "corrupt PNG: the first chunk is not IHDR";
    first = false;
    const std::uint32_t crc_stored = be32(&b[at + 8 + len]);
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), &b[at + 4], static_cast<uInt>(len + 4));
    if (crc != crc_stored) return "corrupt PNG: CRC mismatch in chunk " + type;
    at += 12 + len;
    if (type == "IEND") return {};
  }
}

// JPEG (ITU T.81 annex B): SOI (FF D8) first, EOI (FF D9) last; some writers pad after EOI,
// so the last 64 bytes are searched for it.
std::string jpeg_error(std::span<const std::uint8_t> b) {
  const std::size_t from = b.size() > 64 ? b.size() - 64 : 2;
  for (std::size_t i = b.size() - 1; i > from; --i)
    if (b[i - 1] == 0xFF && b[i] == 0xD9) return {};
  return "truncated JPEG: no end-of-image marker";
}

}  // namespace

std::string image_container_error(std::span<const std::uint8_t> b) {
  static const std::uint8_t png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() >= 8 && std::equal(png_sig, png_sig + 8, b.begin())) return png_error(b);
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return jpeg_error(b);
  return "not a PNG or JPEG file";
}

GrayImage decode_gray_image(std::span<const std::uint8_t> bytes) {
  GrayImage r;
  r.error = image_container_error(bytes);
  if (!r.error.empty()) return r;
  try {
    // imdecode takes a Mat header; the buffer is only read.
    const cv::Mat buf(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<std::uint8_t*>(bytes.data()));
    r.gray = cv::imdecode(buf, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    r.gray.release();
    r.error = "cannot decode: " + e.err;
    return r;
  }
  if (r.gray.empty() || r.gray.type() != CV_8UC1) {
    r.gray.release();
    r.error = "cannot decode the image data";
  }
  return r;
}

GrayImage read_gray_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return {{}, "file not found"};
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> bytes;
  if (in) {
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size >= 0 && size < (std::streamoff{1} << 31)) {
      bytes.resize(static_cast<std::size_t>(size));
      in.read(reinterpret_cast<char*>(bytes.data()), size);
    }
  }
  if (!in) return {{}, "cannot read the file"};
  return decode_gray_image(bytes);
}

}  // namespace luxloc
