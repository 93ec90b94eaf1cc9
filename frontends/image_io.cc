#include "frontends/image_io.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>

#include "datasets/text_util.h"

namespace slam {
namespace {

uint32_t Be16(std::string_view b, size_t i) {
  return (uint32_t{static_cast<uint8_t>(b[i])} << 8) |
         static_cast<uint8_t>(b[i + 1]);
}
uint32_t Be32(std::string_view b, size_t i) {
  return (Be16(b, i) << 16) | Be16(b, i + 2);
}
uint32_t Le16(std::string_view b, size_t i) {
  return (uint32_t{static_cast<uint8_t>(b[i + 1])} << 8) |
         static_cast<uint8_t>(b[i]);
}
uint32_t Le24(std::string_view b, size_t i) {
  return Le16(b, i) | (uint32_t{static_cast<uint8_t>(b[i + 2])} << 16);
}
uint32_t Le32(std::string_view b, size_t i) {
  return Le16(b, i) | (Le16(b, i + 2) << 16);
}

bool JpegSize(std::string_view b, int64_t* width, int64_t* height) {
  size_t pos = 2;  // After SOI (FF D8).
  while (pos + 4 <= b.size()) {
    if (static_cast<uint8_t>(b[pos]) != 0xFF) return false;
    const uint8_t marker = static_cast<uint8_t>(b[pos + 1]);
    if (marker == 0xFF) {  // Fill byte.
      ++pos;
      continue;
    }
    pos += 2;
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;
    if (marker == 0xD9 || marker == 0xDA) return false;  // EOI, SOS first.
    const uint32_t length = Be16(b, pos);
    if (length < 2) return false;
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 &&
                     marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (length < 7 || pos + 7 > b.size()) return false;
      *height = Be16(b, pos + 3);
      *width = Be16(b, pos + 5);
      return *height > 0;  // 0: given later by a DNL marker.
    }
    pos += length;
  }
  return false;
}

// PGM/PPM/PNM (P1-P6): magic, then width and height as decimal tokens
// separated by white space and '#' comments.
bool PnmSize(std::string_view b, int64_t* width, int64_t* height) {
  if (b.size() < 3 || b[0] != 'P' || b[1] < '1' || b[1] > '6') return false;
  size_t pos = 2;
  int64_t values[2];
  for (int64_t& value : values) {
    while (pos < b.size()) {
      if (b[pos] == '#') {
        while (pos < b.size() && b[pos] != '\n') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(b[pos]))) {
        ++pos;
      } else {
        break;
      }
    }
    const size_t start = pos;
    value = 0;
    while (pos < b.size() && pos - start < 10 && b[pos] >= '0' &&
           b[pos] <= '9') {
      value = value * 10 + (b[pos] - '0');
      ++pos;
    }
    if (pos == start) return false;
  }
  *width = values[0];
  *height = values[1];
  return true;
}

}  // namespace

bool ImageHeaderSize(std::string_view b, int64_t* width, int64_t* height) {
  if (b.size() >= 24 && b.substr(0, 8) == "\x89PNG\r\n\x1a\n" &&
      b.substr(12, 4) == "IHDR") {
    *width = Be32(b, 16);
    *height = Be32(b, 20);
    return true;
  }
  if (b.size() >= 4 && static_cast<uint8_t>(b[0]) == 0xFF &&
      static_cast<uint8_t>(b[1]) == 0xD8) {
    return JpegSize(b, width, height);
  }
  if (b.size() >= 30 && b.substr(0, 4) == "RIFF" && b.substr(8, 4) == "WEBP") {
    const std::string_view chunk = b.substr(12, 4);
    if (chunk == "VP8 " && b.substr(23, 3) == "\x9d\x01\x2a") {
      *width = Le16(b, 26) & 0x3FFF;
      *height = Le16(b, 28) & 0x3FFF;
      return true;
    }
    if (chunk == "VP8L" && static_cast<uint8_t>(b[20]) == 0x2F) {
      const uint32_t bits = Le32(b, 21);
      *width = (bits & 0x3FFF) + 1;
      *height = ((bits >> 14) & 0x3FFF) + 1;
      return true;
    }
    if (chunk == "VP8X") {
      *width = int64_t{Le24(b, 24)} + 1;
      *height = int64_t{Le24(b, 27)} + 1;
      return true;
    }
    return false;
  }
  if (b.size() >= 26 && b.substr(0, 2) == "BM") {
    const uint32_t header = Le32(b, 14);
    if (header == 12) {  // BITMAPCOREHEADER: 16-bit sizes.
      *width = Le16(b, 18);
      *height = Le16(b, 20);
    } else {
      *width = static_cast<int32_t>(Le32(b, 18));
      *height = std::abs(int64_t{static_cast<int32_t>(Le32(b, 22))});
    }
    return true;
  }
  return PnmSize(b, width, height);
}

int OrbMinImageSide(int levels, double scale_factor, int edge_threshold) {
  // The coarsest level must keep a pixel (cvRound(side / scale) >= 1) and
  // the finest must leave room inside the border for a feature.
  const double coarsest = std::pow(scale_factor, std::max(0, levels - 1));
  const double side = std::max(2.0 * edge_threshold + 1.0, std::ceil(coarsest));
  return static_cast<int>(std::min(side, 1e9));
}

bool ReadGrayImage(const std::string& path, int min_side, cv::Mat* image,
                   std::string* error, int64_t max_pixels) {
  return ReadImageChecked(path, cv::IMREAD_GRAYSCALE, min_side, image, error,
                          max_pixels);
}

bool ReadImageChecked(const std::string& path, int flags, int min_side,
                      cv::Mat* image, std::string* error, int64_t max_pixels) {
  image->release();
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {  // Dangling link, loop, missing.
    *error = path + ": cannot read the image: " + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    *error = path + ": cannot read the image: not a regular file (" +
             (S_ISDIR(st.st_mode)    ? "a directory"
              : S_ISFIFO(st.st_mode) ? "a FIFO"
                                     : "a device or socket") +
             ")";
    return false;
  }
  std::string bytes;
  if (!text::ReadWholeFile(path, &bytes, error, kMaxImageFileBytes)) {
    return false;
  }
  if (bytes.empty()) {
    *error = path + ": cannot read the image: empty file";
    return false;
  }
  auto check_size = [&](int64_t width, int64_t height, const char* what) {
    if (width <= 0 || height <= 0 || width > max_pixels ||
        height > max_pixels || width * height > max_pixels) {
      *error = path + ": " + what + " " + std::to_string(width) + "x" +
               std::to_string(height) + " pixels (at most " +
               std::to_string(max_pixels) + " pixels are read; not decoded)";
      return false;
    }
    if (width < min_side || height < min_side) {
      *error = path + ": " + std::to_string(width) + "x" +
               std::to_string(height) +
               " pixels: too small for the feature pyramid (each side must "
               "be at least " +
               std::to_string(min_side) + " pixels)";
      return false;
    }
    return true;
  };
  int64_t width = 0, height = 0;
  if (ImageHeaderSize(bytes, &width, &height) &&
      !check_size(width, height, "the header declares")) {
    return false;
  }
  try {
    const cv::Mat data(1, static_cast<int>(bytes.size()), CV_8U, bytes.data());
    *image = cv::imdecode(data, flags);
  } catch (const cv::Exception& e) {
    image->release();
    *error = path + ": cannot decode the image: " + e.err;
    return false;
  }
  if (image->empty()) {
    *error = path +
             ": cannot read the image (corrupt, or not an image format "
             "OpenCV decodes)";
    return false;
  }
  if (!check_size(image->cols, image->rows, "the image is")) {
    image->release();
    return false;
  }
  return true;
}

}  // namespace slam
