#pragma once
// Splits text at every `sep`: "a:b::c" -> {"a", "b", "", "c"}; "" -> {""}. Empty fields are
// kept so a parser can name the one that is missing.
#include <string>
#include <vector>

namespace luxloc {

inline std::vector<std::string> split_text(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(sep, start);
    out.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return out;
    start = end + 1;
  }
}

}  // namespace luxloc
