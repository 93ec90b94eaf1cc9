// Drawing primitives of the plot module (internal to apps/plot/): anti-aliased
// segments and (dashed) polylines at sub-pixel positions, and text anchored
// or rotated, in OpenCV's Hershey font.
#ifndef SLAM_APPS_PLOT_DRAW_H_
#define SLAM_APPS_PLOT_DRAW_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/plot/plot.h"

namespace slam::plot {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kWhite(255, 255, 255);

// Fixed point with 4 fractional bits (the shift of cv::line and friends).
cv::Point Pt(const cv::Point2d& p);

void DrawSegment(cv::Mat& img, const cv::Point2d& a, const cv::Point2d& b,
                 const cv::Scalar& color, int thickness);

// Polyline, optionally dashed (dash pattern in pixels along the path).
void DrawPolyline(cv::Mat& img, const std::vector<cv::Point2d>& pts,
                  const cv::Scalar& color, int thickness, bool dashed);

cv::Size TextSize(const std::string& text, double scale, int thickness,
                  int* baseline = nullptr);

// Text with its anchor: h = -1 left, 0 centre, 1 right; v = -1 top, 0
// middle, 1 baseline-bottom.
void PutText(cv::Mat& img, const std::string& text, cv::Point anchor,
             double scale, int thickness, int h, int v,
             const cv::Scalar& color = kBlack);

// Text rotated 90 degrees counter-clockwise, centred on `center`.
void PutTextVertical(cv::Mat& img, const std::string& text, cv::Point center,
                     double scale, int thickness);

}  // namespace slam::plot

#endif  // SLAM_APPS_PLOT_DRAW_H_
