#pragma once
// The image files of a folder (png, jpg, jpeg, bmp, tif, tiff, pgm, ppm; any case), in name
// order: what `calib camera --images` and `calib rowtime --images` read.
#include <filesystem>
#include <string>
#include <vector>

namespace luxloc::app {

// Throws InputError(dir, 0, "--images", ...) when the folder holds no image file.
std::vector<std::filesystem::path> image_files(const std::string& dir);

}  // namespace luxloc::app
