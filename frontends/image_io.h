// Reading one image for the visual frontends and commands (the stereo
// pipeline, slam vocabulary, slam loops) with the checks that keep any file
// from crashing or exhausting the process:
//   - only a regular file is an image: a FIFO, a directory, a dangling
//     symbolic link or a link loop named like an image is an unreadable
//     image, named as such (never skipped, never waited on);
//   - the size the header declares is checked before anything is decoded
//     (PNG IHDR, JPEG SOFn, WebP VP8/VP8L/VP8X, BMP, PGM/PPM/PNM), so a
//     100-byte file claiming 60000 x 60000 pixels costs nothing; the other
//     formats OpenCV reads are bounded by the decoded size check and by
//     OpenCV's own pixel limit;
//   - OpenCV's exceptions (corrupt data, its size limit) become errors;
//   - an image smaller than `min_side` on a side is refused (the ORB pyramid
//     cannot be built on it, see OrbMinImageSide).
#ifndef SLAM_FRONTENDS_IMAGE_IO_H_
#define SLAM_FRONTENDS_IMAGE_IO_H_

#include <cstdint>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

namespace slam {

// Images larger than this (width x height) are refused: 64 Mpixel, beyond
// any camera these pipelines are meant for, and 64 MB as grey.
constexpr int64_t kMaxImagePixels = int64_t{1} << 26;
// Image files larger than this are refused before reading.
constexpr int64_t kMaxImageFileBytes = int64_t{1} << 28;  // 256 MiB.

// The width and height a PNG, JPEG, WebP, BMP or PNM header declares, from
// the first bytes of the file (`head`; JPEG needs the bytes up to its SOF
// marker, usually well within 64 KiB). False when the format is not one of
// those or the header is cut short or malformed.
bool ImageHeaderSize(std::string_view head, int64_t* width, int64_t* height);

// The smallest image side on which OpenCV's ORB can build its pyramid of
// `levels` levels `scale_factor` apart and find a feature away from the
// `edge_threshold` border (cv::resize asserts on a level of 0 pixels).
int OrbMinImageSide(int levels, double scale_factor, int edge_threshold);

// Reads `path` as 8-bit grey (cv::IMREAD_GRAYSCALE) with the checks above:
// at most `max_pixels` pixels (width x height), sides of at least
// `min_side`. False with "PATH: problem" otherwise.
bool ReadGrayImage(const std::string& path, int min_side, cv::Mat* image,
                   std::string* error, int64_t max_pixels = kMaxImagePixels);

// The same with cv::imdecode's `flags` (e.g. cv::IMREAD_UNCHANGED for 16-bit
// depth images).
bool ReadImageChecked(const std::string& path, int flags, int min_side,
                      cv::Mat* image, std::string* error,
                      int64_t max_pixels = kMaxImagePixels);

}  // namespace slam

#endif  // SLAM_FRONTENDS_IMAGE_IO_H_
