#pragma once
// Building small JSON texts for the outputs (MQTT status, the web page's stream) without
// a JSON library: strings escaped per RFC 8259, numbers passed in already formatted
// (format_fixed / format_time_s), an empty number omitted (unknown, never NaN or null).
#include <string>

namespace luxloc {

// "text" with quotes, backslashes and control characters escaped.
std::string json_string(const std::string& text);

class JsonObject {
 public:
  void add_number(const std::string& key, const std::string& formatted);  // "" : omitted
  void add_string(const std::string& key, const std::string& value);
  void add_object(const std::string& key, const JsonObject& value);
  void add_raw(const std::string& key, const std::string& json);  // an array or object text
  std::string str() const { return "{" + body_ + "}"; }

 private:
  void key(const std::string& k);
  std::string body_;
};

}  // namespace luxloc
