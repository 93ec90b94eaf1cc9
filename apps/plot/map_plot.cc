#include "apps/plot/map_plot.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "apps/plot/plot.h"

namespace slam {
namespace {

// Sub-pixel drawing: coordinates carry this many fractional bits.
constexpr int kShift = 4;

}  // namespace

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
  const int scale = std::max(1, 800 / std::max(image.width, image.height));
  return plot::SavePng(path, RenderMapImage(image, trajectory, scale), error);
}

}  // namespace slam
