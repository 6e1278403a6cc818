#pragma once
// Reads a frame file (PNG or JPEG) to 8-bit gray with a reason when it cannot, and without
// the image libraries' own stderr lines. libpng reports a truncated or corrupt file by
// printing "libpng error: ..." itself (OpenCV installs no error callback), libjpeg prints
// "Corrupt JPEG data: premature end of data segment" and hands back a half-grey image; a
// redirect of fd 2 would race with every other thread. So the file is read into a buffer,
// its container structure is checked here first (PNG: signature, every chunk complete with
// a matching CRC up to IEND; JPEG: SOI at the start, EOI at the end), and only a complete
// file goes to cv::imdecode. A file that passes these checks but whose compressed data is
// still broken can make the libraries print (a crafted file; not seen with cut or
// bit-flipped ones: the CRCs catch those in PNG) — docs/RELIABILITY.md.
#include <cstdint>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <span>
#include <string>

namespace luxloc {

struct GrayImage {
  cv::Mat gray;       // CV_8UC1; empty when unusable
  std::string error;  // why, when empty ("truncated PNG: chunk IDAT ends past the file")
};

// Empty when `bytes` hold a structurally complete PNG or JPEG; otherwise what is wrong.
std::string image_container_error(std::span<const std::uint8_t> bytes);

// Decodes an image held in memory (gray or colour -> gray; sensor orientation, EXIF ignored).
GrayImage decode_gray_image(std::span<const std::uint8_t> bytes);
// Reads and decodes `path`; error "file not found" / "cannot read" / the container error.
GrayImage read_gray_image(const std::filesystem::path& path);

}  // namespace luxloc
