#include "plugins/output/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "core/common/input_error.hpp"

namespace luxloc {

TextFile::TextFile(const std::string& path) : path_(path) {
  if (path == "-") {
    file_ = stdout;
    return;
  }
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw InputError(path, 0, "", std::string("cannot create output file: ") + std::strerror(errno));
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

TextFile::~TextFile() {
  if (!file_) return;
  if (file_ == stdout)
    std::fflush(file_);
  else
    std::fclose(file_);
}

void TextFile::write(std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    throw std::runtime_error("cannot write " + (is_stdout() ? std::string("stdout") : path_) + ": " +
                             std::strerror(errno));
}

void TextFile::flush() {
  if (std::fflush(file_) != 0)
    throw std::runtime_error("cannot write " + (is_stdout() ? std::string("stdout") : path_) + ": " +
                             std::strerror(errno));
}

}  // namespace luxloc
