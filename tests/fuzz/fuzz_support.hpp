#pragma once
// Shared pieces of the libFuzzer targets (tests/fuzz, docs/RELIABILITY.md "Fuzzing").
// A target turns the fuzz input into files or byte streams, calls one parser, and checks
// what the parser promises: bad input ends in an InputError (exit 2) or a counted drop,
// never another exception, a crash, a hang or a non-finite value in what comes out.
// Anything else aborts, which libFuzzer reports as a finding.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace luxloc::fuzz {

// A scratch folder of this process (targets write their input to files there).
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("luxloc-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline void write_file(const std::filesystem::path& p, std::string_view bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Splits the input at lines that hold exactly `marker` (the seed corpora are files joined
// by such lines); at most `parts` pieces, the last one keeps the rest.
inline std::vector<std::string_view> split_parts(std::string_view in, std::string_view marker, std::size_t parts) {
  std::vector<std::string_view> out;
  const std::string sep = "\n" + std::string(marker) + "\n";
  while (out.size() + 1 < parts) {
    const std::size_t at = in.find(sep);
    if (at == std::string_view::npos) break;
    out.push_back(in.substr(0, at + 1));
    in.remove_prefix(at + sep.size());
  }
  out.push_back(in);
  return out;
}

// A broken promise: print it and abort (libFuzzer saves the input as a crash).
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "luxloc fuzz: %s\n", what.c_str());
  std::abort();
}

// Feeds `size` bytes to a stream parser the way a serial port delivers them: in reads of
// 1..max_chunk bytes (the first `first` long, then varying), the clock advancing by `dt` ns
// per read; read(bytes, n, t_end) parses and checks one read.
template <class Read>
void feed_in_reads(const std::uint8_t* data, std::size_t size, std::size_t first, std::size_t max_chunk, std::int64_t t,
                   std::int64_t dt, Read read) {
  std::size_t at = 0, chunk = first;
  while (at < size) {
    const std::size_t n = std::min(chunk, size - at);
    t += dt;
    read(data + at, n, t);
    at += n;
    chunk = 1 + (chunk * 7 + 3) % max_chunk;
  }
}

inline void expect_finite(double v, const char* what) {
  if (!std::isfinite(v)) fail(std::string("non-finite ") + what);
}

}  // namespace luxloc::fuzz
