#include "plugins/output/json_text.hpp"

#include <cstdio>

namespace luxloc {

std::string json_string(const std::string& text) {
  std::string s = "\"";
  s.reserve(text.size() + 2);
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      s += '\\';
      s += ch;
    } else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      s += buf;
    } else {
      s += ch;
    }
  }
  s += '"';
  return s;
}

void JsonObject::key(const std::string& k) {
  if (!body_.empty()) body_ += ',';
  body_ += json_string(k);
  body_ += ':';
}

void JsonObject::add_number(const std::string& k, const std::string& formatted) {
  if (formatted.empty()) return;
  key(k);
  body_ += formatted;
}

void JsonObject::add_string(const std::string& k, const std::string& value) {
  key(k);
  body_ += json_string(value);
}

void JsonObject::add_object(const std::string& k, const JsonObject& value) {
  key(k);
  body_ += value.str();
}

void JsonObject::add_raw(const std::string& k, const std::string& json) {
  key(k);
  body_ += json;
}

}  // namespace luxloc
