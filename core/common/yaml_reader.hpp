#pragma once
// One reader for every OpenCV FileStorage YAML file we take (ledmap.yaml, camera.yaml,
// session.yaml, the IMU calibration): a structural error — a file that does not parse, a
// top level or an entry that is not a mapping, a scalar where a mapping or sequence is
// expected, a wrong type — is an InputError naming the file and the key (exit 2), never one
// of OpenCV's own assertions ("isMap() in function 'operator[]'", which cv::FileNode raises
// when indexed by name while it holds something else).
#include <opencv2/core/persistence.hpp>
#include <string>

namespace luxloc {

class YamlFile {
 public:
  // Reads and parses `path`; `what` names the kind of file in messages ("LED map"). An empty
  // file, or one holding only the %YAML preamble, reads as a mapping with no keys.
  YamlFile(std::string path, const std::string& what);

  const std::string& path() const { return path_; }
  // The top-level value of `key`; an empty node when absent or null (`key:` with no value).
  cv::FileNode operator[](const char* key) const;

  // The member `key` of `map` (empty when absent or null); `where` names the mapping in
  // messages ("LED #3 (id 7)", "anchors", "" for the top level).
  cv::FileNode member(const cv::FileNode& map, const char* key, const std::string& where) const;

  // Typed reads of a present node; InputError(path, key, where + ": ...") on a wrong type.
  double number(const cv::FileNode& n, const std::string& key, const std::string& where) const;  // finite
  int integer(const cv::FileNode& n, const std::string& key, const std::string& where) const;
  std::string string(const cv::FileNode& n, const std::string& key, const std::string& where) const;
  // Checks the node is a sequence / a mapping (for iteration / member()).
  void expect_seq(const cv::FileNode& n, const std::string& key, const std::string& where) const;
  void expect_map(const cv::FileNode& n, const std::string& key, const std::string& where) const;
  // An opencv-matrix (`!!opencv-matrix {rows, cols, dt, data}`) as CV_64F; empty node -> empty Mat.
  cv::Mat matrix(const cv::FileNode& n, const std::string& key) const;

  [[noreturn]] void fail(const std::string& key, const std::string& where, const std::string& what) const;

 private:
  std::string path_;
  cv::FileStorage fs_;
  cv::FileNode root_;  // the first document's top-level mapping; empty for a blank file
};

// Seconds (per started MB of file, plus one such allowance) a YAML parse may take before it
// is given up as looping (yaml_reader.cpp, parse_with_deadline). Default 5; tests shorten it.
double& yaml_parse_timeout_s();

// Absent or `null`.
inline bool yaml_absent(const cv::FileNode& n) { return n.empty() || n.isNone(); }

}  // namespace luxloc
