#include "app/image_folder.hpp"

#include <algorithm>
#include <cctype>

#include "core/common/input_error.hpp"

namespace luxloc::app {

std::vector<std::filesystem::path> image_files(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" ||
                                ext == ".tiff" || ext == ".pgm" || ext == ".ppm"))
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(dir, 0, "--images", "no image files (png, jpg, bmp, tif, pgm) in the folder");
  return files;
}

}  // namespace luxloc::app
