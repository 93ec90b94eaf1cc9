// PNG encoding of the plots (zlib), see plot.h EncodePng.
#include <cstdint>
#include <string>

#include <zlib.h>

#include "apps/plot/plot.h"
#include "datasets/atomic_file.h"

namespace slam::plot {

namespace {

void PutU32(uint32_t v, std::string* out) {
  out->push_back(static_cast<char>(v >> 24));
  out->push_back(static_cast<char>(v >> 16));
  out->push_back(static_cast<char>(v >> 8));
  out->push_back(static_cast<char>(v));
}

void PutChunk(const char* type, const std::string& data, std::string* out) {
  PutU32(static_cast<uint32_t>(data.size()), out);
  const std::string body = std::string(type, 4) + data;
  out->append(body);
  PutU32(static_cast<uint32_t>(
             crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                   static_cast<uInt>(body.size()))),
         out);
}

}  // namespace

bool EncodePng(const cv::Mat& image, std::string* png) {
  if (image.empty() || image.type() != CV_8UC3) return false;
  // Scanlines: filter byte 0 (none), then RGB (OpenCV holds BGR).
  std::string raw;
  raw.reserve(static_cast<size_t>(image.rows) * (image.cols * 3 + 1));
  for (int y = 0; y < image.rows; ++y) {
    raw.push_back(0);
    const cv::Vec3b* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.cols; ++x) {
      raw.push_back(static_cast<char>(row[x][2]));
      raw.push_back(static_cast<char>(row[x][1]));
      raw.push_back(static_cast<char>(row[x][0]));
    }
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string deflated(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(&deflated[0]), &size,
                reinterpret_cast<const Bytef*>(raw.data()),
                static_cast<uLong>(raw.size()), 6) != Z_OK) {
    return false;
  }
  deflated.resize(size);
  png->assign("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  PutU32(static_cast<uint32_t>(image.cols), &ihdr);
  PutU32(static_cast<uint32_t>(image.rows), &ihdr);
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bit RGB, no interlace.
  PutChunk("IHDR", ihdr, png);
  PutChunk("IDAT", deflated, png);
  PutChunk("IEND", "", png);
  return true;
}

bool SavePng(const std::string& path, const cv::Mat& image,
             std::string* error) {
  std::string png;
  if (!EncodePng(image, &png)) {
    *error = path + ": PNG encoding failed";
    return false;
  }
  return WriteFileAtomically(path, png, error);
}

}  // namespace slam::plot
