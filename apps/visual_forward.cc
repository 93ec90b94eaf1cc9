#include "apps/visual_forward.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace slam {

bool IsVisualCommand(const std::string& name) {
  return name == "run" || name == "vocabulary" || name == "loops";
}

int ForwardToVisualBinary(int argc, char** argv) {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("SLAM_VISUAL_BINARY")) {
    candidates.push_back(env);
  }
  std::error_code ec;
  const std::filesystem::path exe =
      std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back((exe.parent_path() / "slam-visual").string());
  candidates.push_back(SLAM_VISUAL_BINARY_PATH);
  std::string tried;
  for (const std::string& path : candidates) {
    if (access(path.c_str(), X_OK) != 0) {
      tried += "\n  " + path + " (" + std::strerror(errno) + ")";
      continue;
    }
    std::vector<char*> args(argv, argv + argc);
    args[0] = const_cast<char*>(path.c_str());
    args.push_back(nullptr);
    execv(path.c_str(), args.data());
    tried += "\n  " + path + " (" + std::strerror(errno) + ")";
  }
  std::cerr << "slam " << (argc > 1 ? argv[1] : "")
            << ": this command is run by slam-visual, which was not found; "
               "tried:"
            << tried << "\n";
  return 1;
}

int RunForwardedCommand(const std::vector<std::string>&) {
  std::cerr << "slam: internal error: an image command was not forwarded to "
               "slam-visual\n";
  return 1;
}

}  // namespace slam
