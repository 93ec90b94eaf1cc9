#include "apps/plot_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "datasets/atomic_file.h"

namespace slam {
namespace {

std::vector<std::string> Candidates() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv("SLAM_PLOT_MODULE")) paths.push_back(env);
  std::error_code ec;
  const std::filesystem::path exe =
      std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / "libslam_plot.so").string());
  paths.push_back(SLAM_PLOT_MODULE_PATH);
  return paths;
}

}  // namespace

bool LoadPlotModuleSymbol(const char* name, void** symbol, std::string* error) {
  // The handle is process-wide state by nature (dlopen keeps it anyway);
  // std::call_once keeps the load thread-safe.
  static std::once_flag once;
  static void* handle = nullptr;
  static std::string load_error;
  std::call_once(once, [] {
    std::string tried;
    for (const std::string& path : Candidates()) {
      if (!std::filesystem::exists(path)) {
        tried += "\n  " + path + " (absent)";
        continue;
      }
      handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle != nullptr) return;
      tried += "\n  " + path + " (" + dlerror() + ")";
    }
    load_error = "cannot load the plot module libslam_plot.so; tried:" + tried;
  });
  if (handle == nullptr) {
    *error = load_error;
    return false;
  }
  // The module has its own copy of datasets/atomic_file.cc: its writes join
  // the caller's output stage (published or discarded with the command's).
  using SetStage = void (*)(OutputStage*);
  if (void* set_stage = dlsym(handle, "SlamSetOutputStage")) {
    reinterpret_cast<SetStage>(set_stage)(OutputStage::Current());
  }
  *symbol = dlsym(handle, name);
  if (*symbol == nullptr) {
    *error = std::string("the plot module has no symbol ") + name;
    return false;
  }
  return true;
}

}  // namespace slam
