// Helpers shared by the tests: where real data and fixtures live, temporary
// directories, and running the `slam` binary.
#ifndef SLAM_TESTS_TEST_UTIL_H_
#define SLAM_TESTS_TEST_UTIL_H_

#include <sys/wait.h>
#include <unistd.h>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gtest/gtest.h"

namespace slam::testing {

// $SLAM_DATASETS, else ../shared/datasets beside the checkout.
inline std::string DatasetsDir() {
  const char* env = std::getenv("SLAM_DATASETS");
  return env != nullptr ? std::string(env)
                        : std::string(SLAM_DEFAULT_DATASETS_DIR);
}

inline std::string DatasetPath(const std::string& relative) {
  return DatasetsDir() + "/" + relative;
}

// Handmade fixtures committed beside the tests.
inline std::string FixturePath(const std::string& name) {
  return std::string(SLAM_TEST_DATA_DIR) + "/" + name;
}

// The shipped configs (configs/ at the repository root).
inline std::string ConfigPath(const std::string& name) {
  return std::string(SLAM_TEST_DATA_DIR) + "/../../configs/" + name;
}

// The directories TempDir made; removed when the test process exits (each
// test runs in a process of its own under ctest), unless $SLAM_KEEP_TEST_DIRS
// is set (to look at the files of a failing test).
class TempDirCleanup {
 public:
  static TempDirCleanup& Get() {
    static TempDirCleanup cleanup;
    return cleanup;
  }
  void Add(const std::filesystem::path& dir) { dirs_.push_back(dir); }
  ~TempDirCleanup() {
    if (std::getenv("SLAM_KEEP_TEST_DIRS") != nullptr) return;
    for (const std::filesystem::path& dir : dirs_) {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  }

 private:
  std::vector<std::filesystem::path> dirs_;
};

// A fresh empty directory under the system temp dir, named after the test.
inline std::string TempDir() {
  const ::testing::TestInfo* info =
      ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("slam_test_" + std::string(info->test_suite_name()) + "_" +
       info->name() + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TempDirCleanup::Get().Add(dir);
  return dir.string();
}

// Whole-file text read (empty if absent) and write.
inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

inline bool Exists(const std::string& path) {
  return std::filesystem::exists(path);
}

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// 100 bytes starting like a PNG file whose header (IHDR) declares
// width x height 8-bit grey pixels, followed by junk: what a decoder that
// trusts the header would allocate for.
inline std::string PngDeclaring(uint32_t width, uint32_t height) {
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (uint32_t v : {width, height}) {
    for (int shift = 24; shift >= 0; shift -= 8) png += char(v >> shift);
  }
  png += std::string("\x08\0\0\0\0", 5);  // Depth 8, grey, no interlace.
  png.resize(100, '\x5a');
  return png;
}

// Runs the slam binary with `args`; returns its exit code. stdout and stderr
// go to `log` (a file path) when given.
inline int RunSlam(const std::string& args, const std::string& log = "") {
  std::string cmd = std::string(SLAM_BINARY) + " " + args;
  if (!log.empty()) cmd += " > '" + log + "' 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A run of the slam binary with stdout and stderr captured separately
// (through files in `dir`).
struct CapturedRun {
  int code = -1;
  std::string out, err;
};

inline CapturedRun RunSlamCaptured(const std::string& args,
                                   const std::string& dir) {
  CapturedRun run;
  run.code = RunSlam(args + " > '" + dir + "/stdout' 2> '" + dir + "/stderr'");
  run.out = ReadText(dir + "/stdout");
  run.err = ReadText(dir + "/stderr");
  return run;
}

}  // namespace slam::testing

// Skips the current test with a message when a real-data file is absent.
#define SLAM_REQUIRE_DATASET(path)                                          \
  do {                                                                      \
    if (!std::filesystem::exists(path)) {                                   \
      GTEST_SKIP() << "dataset not found: " << (path)                       \
                   << " (set SLAM_DATASETS to the shared datasets folder)"; \
    }                                                                       \
  } while (0)

#endif  // SLAM_TESTS_TEST_UTIL_H_
