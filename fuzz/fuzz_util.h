// Helpers of the libFuzzer targets (fuzz/CMakeLists.txt): the readers take
// paths, so each input is written to a scratch file of the process first.
#ifndef SLAM_FUZZ_FUZZ_UTIL_H_
#define SLAM_FUZZ_FUZZ_UTIL_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "datasets/g2o_io.h"

namespace slam::fuzz {

// A directory of this process under $TMPDIR (default /tmp), removed at exit.
inline const std::string& ScratchDir() {
  static const std::string* dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    auto* d = new std::string(std::string(tmp != nullptr ? tmp : "/tmp") +
                              "/slam_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(*d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(ScratchDir(), ec);
    });
    return d;
  }();
  return *dir;
}

// Writes bytes to ScratchDir()/name (creating parent folders) and returns
// the path.
inline std::string WriteScratch(const std::string& name, const uint8_t* data,
                                size_t size) {
  const std::string path = ScratchDir() + "/" + name;
  std::filesystem::create_directories(
      std::filesystem::path(path).parent_path());
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

inline std::string WriteScratch(const std::string& name,
                                const std::string& text) {
  return WriteScratch(name, reinterpret_cast<const uint8_t*>(text.data()),
                      text.size());
}

// A reader must either succeed or explain why: an empty error on failure is
// a bug (the fuzzer stops on abort()).
inline void CheckResult(bool ok, const std::string& error) {
  if (!ok && error.empty()) std::abort();
}

// Runs a pose-graph reader from text (ReadG2oFromText, ReadToroFromText,
// ReadIsamFromText) with options picked by the first byte.
template <typename Reader>
int FuzzGraphReader(Reader read, const char* name, const uint8_t* data,
                    size_t size) {
  GraphReadOptions options;
  if (size > 0) {
    options.repair_information = (data[0] & 1) != 0;
    options.allow_missing_vertices = (data[0] & 2) != 0;
    options.skip_unknown_tags = (data[0] & 4) != 0;
  }
  Graph graph;
  GraphReadReport report;
  std::string error;
  const bool ok =
      read(name, std::string_view(reinterpret_cast<const char*>(data), size),
           options, &graph, &report, &error);
  CheckResult(ok, error);
  return 0;
}

}  // namespace slam::fuzz

#endif  // SLAM_FUZZ_FUZZ_UTIL_H_
