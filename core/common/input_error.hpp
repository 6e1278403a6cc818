#pragma once
// Bad input policy (SPEC.md "Exit codes"): unusable input raises InputError naming the
// file, line and field; the CLI maps it to exit code 2. Playback instead skips and counts
// bad rows (see BadRowCounter), so one broken row never loses the good ones.
#include <stdexcept>
#include <string>

namespace luxloc {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string field, const std::string& what)
      : std::runtime_error(format(file, line, field, what)),
        file_(std::move(file)),
        line_(line),
        field_(std::move(field)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 0 when not line-based
  const std::string& field() const { return field_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& field,
                            const std::string& what) {
    // Built with append(): GCC 12 warns falsely (-Wrestrict) on chained operator+.
    std::string s;
    s.reserve(file.size() + field.size() + what.size() + 32);
    s.append(file);
    if (line > 0) s.append(":").append(std::to_string(line));
    if (!field.empty()) s.append(": field '").append(field).append("'");
    s.append(": ").append(what);
    return s;
  }

  std::string file_;
  int line_;
  std::string field_;
};

}  // namespace luxloc
