#pragma once
// Reader for SPEC.md's CSV files: a header row naming the columns (found by name, unknown
// ones ignored), '#' comment lines, blank lines skipped. Every problem is an InputError
// naming the file, the line and the field, so callers can either stop (exit 2) or skip
// and count the row (playback).
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace luxloc {

class CsvReader {
 public:
  // Opens the file and reads its header; throws InputError when it cannot.
  explicit CsvReader(std::string path);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  int column(std::string_view name) const;          // -1 when absent
  int require_column(std::string_view name) const;  // throws InputError (header line)

  // Advances to the next data row; false at end of file.
  bool next_row();
  int line() const { return line_; }  // 1-based line number of the current row
  std::size_t size() const { return fields_.size(); }
  std::string_view field(int col) const;  // throws InputError when the row is too short
  // Parses a finite double; throws InputError(file, line, column name) when it is not.
  double number(int col) const;
  // Like number() but an empty field (or absent column, col < 0) yields `fallback`.
  double number_or(int col, double fallback) const;
  long long integer(int col) const;
  std::string_view column_name(int col) const;

 private:
  std::string path_;
  std::ifstream in_;
  std::vector<std::string> header_;
  std::string row_;
  std::vector<std::string_view> fields_;
  int line_ = 0;
};

}  // namespace luxloc
