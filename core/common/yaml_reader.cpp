#include "core/common/yaml_reader.hpp"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <opencv2/core.hpp>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

std::string type_name(const cv::FileNode& n) {
  if (n.isMap()) return "a mapping";
  if (n.isSeq()) return "a sequence";
  if (n.isString()) return "a string ('" + static_cast<std::string>(n) + "')";
  if (n.isInt() || n.isReal()) return "a number";
  if (n.isNone() || n.empty()) return "empty";
  return "an unknown node";
}

// Only "%YAML..." / "---" / comments / blank lines: nothing to parse.
bool blank_text(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  bool blank = true;
  char line[256];
  while (blank && std::fgets(line, sizeof line, f)) {
    std::string l(line);
    while (!l.empty() && (l.back() == '\n' || l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) l.pop_back();
    std::size_t i = l.find_first_not_of(" \t");
    if (i == std::string::npos) continue;
    l = l.substr(i);
    if (l[0] == '#' || l.rfind("%YAML", 0) == 0 || l == "---" || l == "...") continue;
    blank = false;
  }
  std::fclose(f);
  return blank;
}

// OpenCV 4.6's YAML parser never returns on some malformed input, found by the fuzz target
// fuzz_yaml: a document marker run into text ("----Y0" then "----t"), and a byte >= 0x80 in
// a key ("half_po\xfder_angle_deg") both loop forever inside FileStorage::open; 0xff bytes
// made it throw std::length_error. So the text is checked first: a line starting with "---"
// must be a document marker ("---" alone or followed by a blank or a comment), and outside
// comments only printable ASCII, tabs and line ends may appear (our files hold numbers,
// names and ids; UTF-8 is fine in comments). Returns the problem and its 1-based line.
struct TextProblem {
  int line = 0;
  std::string what;
};

std::optional<TextProblem> text_problem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string l;
  bool ended = false;  // after a document end marker "..."
  for (int n = 1; std::getline(in, l); ++n) {
    // A UTF-8 byte-order mark (what some Windows editors write first) is not text.
    if (n == 1 && l.rfind("\xEF\xBB\xBF", 0) == 0) l.erase(0, 3);
    if (l.size() > 3 && l.rfind("---", 0) == 0 && l[3] != ' ' && l[3] != '\t' && l[3] != '\r' && l[3] != '#')
      return TextProblem{n, "a line starting with '---' that is not a document marker ('---' alone)"};
    bool after_blank = true;
    for (std::size_t i = 0; i < l.size(); ++i) {
      const auto c = static_cast<unsigned char>(l[i]);
      if (c == '#' && after_blank) break;  // a comment runs to the end of the line
      after_blank = c == ' ' || c == '\t';
      if (c >= 0x80 || (c < 0x20 && c != '\t' && c != '\r')) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02x", c);
        return TextProblem{n, std::string("byte ") + hex + " in column " + std::to_string(i + 1) +
                                  " (outside comments only printable ASCII is read)"};
      }
    }
    // Text after a document end marker ("..." then "   - { id:3 ... }": a line of the map
    // run into the marker, fuzz_yaml) also loops forever inside FileStorage::open: after a
    // "..." only blank lines, comments or a new document ("---", "%YAML") may follow.
    if (l.rfind("...", 0) == 0) {
      const std::size_t after = l.find_first_not_of(" \t\r", 3);
      if (after != std::string::npos && (l[after] != '#' || after == 3))
        return TextProblem{n, "text after the document end marker '...' on its line"};
      ended = true;
    } else if (ended) {
      const std::size_t text = l.find_first_not_of(" \t\r");
      if (text == std::string::npos || l[text] == '#') continue;
      if (l.rfind("---", 0) != 0 && l.rfind("%", 0) != 0)
        return TextProblem{n, "text after the document end marker '...' (only comments may follow it)"};
      ended = false;
    }
  }
  return std::nullopt;
}

// OpenCV 4.6's parser can also loop forever on malformed indentation that no text rule
// above names (fuzz_yaml, seed 3: "%YAML:1.0" / " - a" / "1-m-"), and more such inputs are
// likely. So the parse itself runs on a thread of its own under a deadline: a parse that
// finishes hands its FileStorage over (a handle: no copy of the tree); one that does not is
// an InputError naming the file. A thread cannot be stopped, so the looping parse is left
// to spin on its own copy of the state until the process exits, which it does at once on
// every path that reads YAML (an InputError is exit 2). Generous on purpose: a 5000-LED map
// (~360 kB) is written, parsed and checked in < 0.2 s on the 2-core development machine (the
// test below the reader's), so 5 s + 5 s per MB is > 25x that; only a parse that is not
// going to finish reaches it.
// The parsed FileStorage (and a parse error's exception) is handed over as the only
// reference, taken out of the job under the lock: OpenCV's parse tree is then freed by the
// reading thread, never by the parse thread, whose ParseJob may outlive the read. TSan
// caught the old version, where a copy left in the job freed the tree on the parse thread.
struct ParseJob {
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  std::unique_ptr<cv::FileStorage> fs;
  std::exception_ptr error;
};

cv::FileStorage parse_with_deadline(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const double mb = ec ? 0.0 : static_cast<double>(bytes) / 1e6;
  const auto deadline = std::chrono::milliseconds(static_cast<long long>(1000.0 * (yaml_parse_timeout_s() * (1.0 + mb))));
  auto job = std::make_shared<ParseJob>();
  std::thread([job, path] {
    auto fs = std::make_unique<cv::FileStorage>();
    std::exception_ptr error;
    try {
      if (!fs->open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML)) fs.reset();
    } catch (...) {
      error = std::current_exception();
      fs.reset();
    }
    std::lock_guard lock(job->m);
    job->fs = std::move(fs);
    job->error = std::move(error);
    job->done = true;
    job->cv.notify_one();
  }).detach();
  std::unique_lock lock(job->m);
  if (!job->cv.wait_for(lock, deadline, [&] { return job->done; }))
    throw InputError(path, 0, "",
                     "the YAML parser did not finish within " + std::to_string(deadline.count() / 1000) +
                         " s (OpenCV's parser loops on some malformed indentation): not a valid " + what);
  const std::unique_ptr<cv::FileStorage> fs = std::move(job->fs);
  if (const std::exception_ptr error = std::exchange(job->error, nullptr)) std::rethrow_exception(error);
  if (!fs || !fs->isOpened()) throw InputError(path, 0, "", "cannot open " + what);
  return *fs;
}

}  // namespace

double& yaml_parse_timeout_s() {
  static double seconds = 5.0;
  return seconds;
}

YamlFile::YamlFile(std::string path, const std::string& what) : path_(std::move(path)) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path_, ec)) throw InputError(path_, 0, "", "cannot open " + what);
  if (blank_text(path_)) return;
  if (const auto bad = text_problem(path_)) throw InputError(path_, bad->line, "", bad->what + ": not a valid " + what);
  try {
    fs_ = parse_with_deadline(path_, what);
    root_ = fs_.root();
  } catch (const InputError&) {
    throw;
  } catch (const cv::Exception& e) {
    throw InputError(path_, 0, "", "not a valid OpenCV YAML " + what + ": " + e.err);
  } catch (const std::exception& e) {
    // OpenCV's parser lets some of its own failures out as other exceptions (found by the
    // fuzz target fuzz_yaml: a std::length_error from a malformed key).
    throw InputError(path_, 0, "", "not a valid OpenCV YAML " + what + " (the parser failed: " + e.what() + ")");
  }
  if (yaml_absent(root_)) return;
  if (!root_.isMap()) fail("", "", "the top level is " + type_name(root_) + ", expected a mapping of keys");
}

void YamlFile::fail(const std::string& key, const std::string& where, const std::string& what) const {
  throw InputError(path_, 0, key, where.empty() ? what : where + ": " + what);
}

cv::FileNode YamlFile::member(const cv::FileNode& map, const char* key, const std::string& where) const {
  if (yaml_absent(map)) return {};
  if (!map.isMap()) fail(key, where, "is " + type_name(map) + ", expected a mapping");
  try {
    cv::FileNode n = map[key];
    return yaml_absent(n) ? cv::FileNode() : n;
  } catch (const cv::Exception& e) {
    fail(key, where, "unreadable: " + e.err);
  }
}

cv::FileNode YamlFile::operator[](const char* key) const { return member(root_, key, ""); }

double YamlFile::number(const cv::FileNode& n, const std::string& key, const std::string& where) const {
  if (!n.isReal() && !n.isInt()) fail(key, where, "not a number (" + type_name(n) + ")");
  const double v = static_cast<double>(n);
  if (!std::isfinite(v)) fail(key, where, "not finite");
  return v;
}

int YamlFile::integer(const cv::FileNode& n, const std::string& key, const std::string& where) const {
  if (!n.isInt()) fail(key, where, "not an integer (" + type_name(n) + ")");
  return static_cast<int>(n);
}

std::string YamlFile::string(const cv::FileNode& n, const std::string& key, const std::string& where) const {
  if (!n.isString()) fail(key, where, "not a string (" + type_name(n) + ")");
  return static_cast<std::string>(n);
}

void YamlFile::expect_seq(const cv::FileNode& n, const std::string& key, const std::string& where) const {
  if (!n.isSeq()) fail(key, where, "is " + type_name(n) + ", expected a sequence");
}

void YamlFile::expect_map(const cv::FileNode& n, const std::string& key, const std::string& where) const {
  if (!n.isMap()) fail(key, where, "is " + type_name(n) + ", expected a mapping");
}

cv::Mat YamlFile::matrix(const cv::FileNode& n, const std::string& key) const {
  if (yaml_absent(n)) return {};
  // An opencv-matrix is a mapping {rows, cols, dt, data}; anything else makes OpenCV's
  // reader assert, so check the shape first.
  if (!n.isMap()) fail(key, "", "is " + type_name(n) + ", expected an opencv-matrix {rows, cols, dt, data}");
  for (const char* k : {"rows", "cols"}) {
    const cv::FileNode f = member(n, k, key);
    if (yaml_absent(f) || !f.isInt() || static_cast<int>(f) <= 0 || static_cast<int>(f) > 4096)
      fail(key, "", std::string("opencv-matrix: '") + k + "' must be an integer 1..4096");
  }
  const cv::FileNode dt = member(n, "dt", key);
  if (yaml_absent(dt) || !dt.isString()) fail(key, "", "opencv-matrix: 'dt' must be a type string (d, f, i...)");
  const cv::FileNode data = member(n, "data", key);
  if (yaml_absent(data) || !data.isSeq()) fail(key, "", "opencv-matrix: 'data' must be a sequence of numbers");
  const std::size_t want = static_cast<std::size_t>(static_cast<int>(n["rows"])) * static_cast<std::size_t>(static_cast<int>(n["cols"]));
  if (data.size() != want)
    fail(key, "", "opencv-matrix: 'data' holds " + std::to_string(data.size()) + " values, rows x cols = " +
                      std::to_string(want));
  for (auto it = data.begin(); it != data.end(); ++it)
    if (!(*it).isReal() && !(*it).isInt()) fail(key, "", "opencv-matrix: 'data' holds something that is not a number");
  cv::Mat m;
  try {
    n >> m;
  } catch (const cv::Exception& e) {
    fail(key, "", "not an opencv-matrix: " + e.err);
  }
  if (m.empty()) fail(key, "", "not an opencv-matrix");
  if (m.channels() != 1) fail(key, "", "opencv-matrix: one channel expected");
  m.convertTo(m, CV_64F);
  for (int i = 0; i < m.rows * m.cols; ++i)
    if (!std::isfinite(m.at<double>(i))) fail(key, "", "holds a non-finite value");
  return m;
}

}  // namespace luxloc
