#include "core/common/csv_reader.hpp"

#include <charconv>
#include <cmath>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void split(std::string_view row, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = row.find(',', start);
    out.push_back(trim(row.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

bool skippable(std::string_view s) {
  s = trim(s);
  return s.empty() || s.front() == '#';
}

}  // namespace

CsvReader::CsvReader(std::string path) : path_(std::move(path)), in_(path_, std::ios::binary) {
  if (!in_) throw InputError(path_, 0, "", "cannot open file");
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    if (line_ == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (skippable(line)) continue;
    std::vector<std::string_view> cols;
    split(line, cols);
    for (auto c : cols) header_.emplace_back(c);
    return;
  }
  throw InputError(path_, line_, "", "no header row (expected column names)");
}

int CsvReader::column(std::string_view name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return static_cast<int>(i);
  return -1;
}

int CsvReader::require_column(std::string_view name) const {
  const int c = column(name);
  if (c < 0) {
    std::string have;
    for (const auto& h : header_) have += (have.empty() ? "" : ",") + h;
    throw InputError(path_, 1, std::string(name), "required column missing (header has: " + have + ")");
  }
  return c;
}

bool CsvReader::next_row() {
  while (std::getline(in_, row_)) {
    ++line_;
    if (skippable(row_)) continue;
    split(row_, fields_);
    return true;
  }
  fields_.clear();
  return false;
}

std::string_view CsvReader::column_name(int col) const {
  return (col >= 0 && static_cast<std::size_t>(col) < header_.size()) ? std::string_view(header_[static_cast<std::size_t>(col)])
                                                                       : std::string_view("?");
}

std::string_view CsvReader::field(int col) const {
  if (col < 0 || static_cast<std::size_t>(col) >= fields_.size())
    throw InputError(path_, line_, std::string(column_name(col)),
                     "row has " + std::to_string(fields_.size()) + " fields, the header " +
                         std::to_string(header_.size()));
  return fields_[static_cast<std::size_t>(col)];
}

double CsvReader::number(int col) const {
  const std::string_view s = field(col);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
    throw InputError(path_, line_, std::string(column_name(col)), "not a number: '" + std::string(s) + "'");
  if (!std::isfinite(v))
    throw InputError(path_, line_, std::string(column_name(col)), "not finite: '" + std::string(s) + "'");
  return v;
}

double CsvReader::number_or(int col, double fallback) const {
  if (col < 0 || static_cast<std::size_t>(col) >= fields_.size() || fields_[static_cast<std::size_t>(col)].empty())
    return fallback;
  return number(col);
}

long long CsvReader::integer(int col) const {
  const std::string_view s = field(col);
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
    throw InputError(path_, line_, std::string(column_name(col)), "not an integer: '" + std::string(s) + "'");
  return v;
}

}  // namespace luxloc
