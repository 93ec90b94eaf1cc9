#include "frontends/rgbd/rgbd_camera.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace slam {
namespace {

namespace fs = std::filesystem;

std::string Lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return s;
}

// "fr1" etc. only as a word of the name (between non-alphanumerics).
bool HasWord(const std::string& name, const std::string& word) {
  for (size_t pos = name.find(word); pos != std::string::npos;
       pos = name.find(word, pos + 1)) {
    const size_t end = pos + word.size();
    const bool start_ok =
        pos == 0 || !std::isalnum(static_cast<unsigned char>(name[pos - 1]));
    const bool end_ok = end == name.size() ||
                        !std::isalnum(static_cast<unsigned char>(name[end]));
    if (start_ok && end_ok) return true;
  }
  return false;
}

}  // namespace

bool TumCameraPreset(const std::string& name, RgbdCamera* camera) {
  RgbdCamera c;
  c.name = name;
  if (name == "freiburg1") {
    c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
    c.k1 = 0.2624, c.k2 = -0.9531, c.p1 = -0.0054, c.p2 = 0.0026, c.k3 = 1.1633;
  } else if (name == "freiburg2") {
    c.fx = 520.9, c.fy = 521.0, c.cx = 325.1, c.cy = 249.7;
    c.k1 = 0.2312, c.k2 = -0.7849, c.p1 = -0.0033, c.p2 = -0.0001,
    c.k3 = 0.9172;
  } else if (name == "freiburg3") {
    c.fx = 535.4, c.fy = 539.2, c.cx = 320.1, c.cy = 247.6;
  } else {
    return false;
  }
  *camera = c;
  return true;
}

std::string GuessTumCameraPreset(const std::string& folder) {
  fs::path p = fs::path(folder).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // "dir/".
  const std::string name = Lowercase(p.filename().string());
  std::string found;
  for (int i = 1; i <= 3; ++i) {
    const std::string n = std::to_string(i);
    if (name.find("freiburg" + n) != std::string::npos ||
        HasWord(name, "fr" + n)) {
      if (!found.empty()) return "";  // Names several: no guess.
      found = "freiburg" + n;
    }
  }
  return found;
}

}  // namespace slam
