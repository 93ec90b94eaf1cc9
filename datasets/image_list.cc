#include "datasets/image_list.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace slam {

bool NaturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie])))
        ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je])))
        ++je;
      // Compare by value: strip leading zeros, then length, then digits.
      size_t is = i, js = j;
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      const int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      if (ie - i != je - j) return ie - i < je - j;  // "01" after "1".
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j])
        return static_cast<unsigned char>(a[i]) <
               static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

bool ListImages(const std::string& dir, std::vector<std::string>* paths,
                std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir + ": not a folder (no such directory)";
    return false;
  }
  std::vector<std::string> names;
  // Every entry named like an image is one: a FIFO, a folder or a broken
  // link among them is an unreadable image (frontends/image_io.h says
  // which), never silently left out (a ground truth indexes the images).
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".bmp" ||
        ext == ".pgm" || ext == ".ppm" || ext == ".tif" || ext == ".tiff" ||
        ext == ".webp") {
      names.push_back(entry.path().filename().string());
    }
  }
  if (ec) {
    *error = dir + ": cannot list: " + ec.message();
    return false;
  }
  if (names.empty()) {
    *error =
        dir + ": no images (jpg, png, bmp, pgm, ppm, tif, webp) in the folder";
    return false;
  }
  std::sort(names.begin(), names.end(), NaturalLess);
  paths->clear();
  for (const std::string& name : names)
    paths->push_back((fs::path(dir) / name).string());
  return true;
}

}  // namespace slam
