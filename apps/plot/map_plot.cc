#include "apps/plot/map_plot.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "apps/map_png.h"
#include "apps/plot/plot.h"

namespace slam {
namespace {

// Sub-pixel drawing: coordinates carry this many fractional bits.
constexpr int kShift = 4;

}  // namespace

MapImage DownsampleMapImage(const MapImage& image, int max_side) {
  const int64_t longest = std::max(image.width, image.height);
  if (max_side <= 0 || longest <= max_side) return image;
  const int64_t k = (longest + max_side - 1) / max_side;
  MapImage out;
  out.width = static_cast<int>((image.width + k - 1) / k);
  out.height = static_cast<int>((image.height + k - 1) / k);
  out.resolution = image.resolution * static_cast<double>(k);
  out.origin_x = image.origin_x;
  out.origin_y = image.origin_y;
  out.pixels.assign(static_cast<size_t>(out.width) * out.height, kPixelUnknown);
  // Rows are counted from the top but blocks from the bottom (the origin),
  // as ToImage merges them.
  for (int64_t r = 0; r < image.height; ++r) {
    const int64_t out_row = out.height - 1 - (image.height - 1 - r) / k;
    const uint8_t* in = &image.pixels[static_cast<size_t>(r) * image.width];
    uint8_t* row = &out.pixels[static_cast<size_t>(out_row) * out.width];
    for (int64_t c = 0; c < image.width; ++c) {
      row[c / k] = MergeMapPixels(row[c / k], in[c]);
    }
  }
  return out;
}

cv::Mat RenderMapImage(const MapImage& image,
                       const std::vector<Eigen::Vector2d>& trajectory,
                       int scale) {
  scale = std::max(1, scale);
  cv::Mat gray(image.height, image.width, CV_8UC1,
               const_cast<uint8_t*>(image.pixels.data()));
  cv::Mat big;
  cv::resize(gray, big, cv::Size(), scale, scale, cv::INTER_NEAREST);
  cv::Mat bgr;
  cv::cvtColor(big, bgr, cv::COLOR_GRAY2BGR);
  if (trajectory.empty()) return bgr;
  const double pixels_per_metre = scale / image.resolution;
  const double top = image.height * scale;
  std::vector<cv::Point> points;
  points.reserve(trajectory.size());
  for (const Eigen::Vector2d& p : trajectory) {
    const double col = (p.x() - image.origin_x) * pixels_per_metre;
    const double row = top - (p.y() - image.origin_y) * pixels_per_metre;
    points.emplace_back(static_cast<int>(std::lround(col * (1 << kShift))),
                        static_cast<int>(std::lround(row * (1 << kShift))));
  }
  const int thickness = std::max(1, scale / 2);
  cv::polylines(bgr, points, false, plot::kBlue, thickness, cv::LINE_AA,
                kShift);
  const int radius = std::max(3, 2 * thickness) << kShift;
  cv::circle(bgr, points.front(), radius, plot::kGreen, cv::FILLED, cv::LINE_AA,
             kShift);
  cv::circle(bgr, points.back(), radius, plot::kRed, cv::FILLED, cv::LINE_AA,
             kShift);
  return bgr;
}

bool WriteMapPngImpl(const std::string& path, const MapImage& image,
                     const std::vector<Eigen::Vector2d>& trajectory,
                     std::string* error) {
  if (image.width <= 0 || image.height <= 0) {
    *error = path + ": empty map (no scan observed any cell)";
    return false;
  }
  const MapImage fitted = DownsampleMapImage(image, kMapPngMaxSide);
  const int scale = std::max(1, 800 / std::max(fitted.width, fitted.height));
  return plot::SavePng(path, RenderMapImage(fitted, trajectory, scale), error);
}

}  // namespace slam
