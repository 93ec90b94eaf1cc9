#include "apps/plot/draw.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace slam::plot {

cv::Point Pt(const cv::Point2d& p) {
  // Fixed point with 4 fractional bits for sub-pixel anti-aliased drawing.
  return cv::Point(static_cast<int>(std::lround(p.x * 16.0)),
                   static_cast<int>(std::lround(p.y * 16.0)));
}

void DrawSegment(cv::Mat& img, const cv::Point2d& a, const cv::Point2d& b,
                 const cv::Scalar& color, int thickness) {
  cv::line(img, Pt(a), Pt(b), color, thickness, cv::LINE_AA, 4);
}

// Polyline, optionally dashed (dash pattern in pixels along the path).
void DrawPolyline(cv::Mat& img, const std::vector<cv::Point2d>& pts,
                  const cv::Scalar& color, int thickness, bool dashed) {
  if (pts.size() < 2) return;
  if (!dashed) {
    std::vector<cv::Point> p;
    p.reserve(pts.size());
    for (const auto& q : pts) p.push_back(Pt(q));
    cv::polylines(img, p, false, color, thickness, cv::LINE_AA, 4);
    return;
  }
  const double on = 10.0, off = 6.0;
  double phase = 0.0;  // Position within the on+off period.
  for (size_t i = 1; i < pts.size(); ++i) {
    cv::Point2d a = pts[i - 1];
    const cv::Point2d b = pts[i];
    double len = std::hypot(b.x - a.x, b.y - a.y);
    const cv::Point2d dir = len > 0 ? (b - a) * (1.0 / len) : cv::Point2d(0, 0);
    while (len > 1e-9) {
      const bool drawing = phase < on;
      const double left = drawing ? on - phase : on + off - phase;
      const double step = std::min(left, len);
      const cv::Point2d c = a + dir * step;
      if (drawing) DrawSegment(img, a, c, color, thickness);
      phase += step;
      if (phase >= on + off - 1e-9) phase = 0.0;
      len -= step;
      a = c;
    }
  }
}

cv::Size TextSize(const std::string& text, double scale, int thickness,
                  int* baseline) {
  int b = 0;
  cv::Size s = cv::getTextSize(text, kFont, scale, thickness, &b);
  if (baseline) *baseline = b;
  return s;
}

// Text with its anchor: h = -1 left, 0 centre, 1 right; v = -1 top, 0
// middle, 1 baseline-bottom.
void PutText(cv::Mat& img, const std::string& text, cv::Point anchor,
             double scale, int thickness, int h, int v,
             const cv::Scalar& color) {
  const cv::Size s = TextSize(text, scale, thickness);
  int x = anchor.x;
  if (h == 0) x -= s.width / 2;
  if (h == 1) x -= s.width;
  int y = anchor.y;
  if (v == -1) y += s.height;
  if (v == 0) y += s.height / 2;
  cv::putText(img, text, cv::Point(x, y), kFont, scale, color, thickness,
              cv::LINE_AA);
}

// Text rotated 90 degrees counter-clockwise, centred on `center`.
void PutTextVertical(cv::Mat& img, const std::string& text, cv::Point center,
                     double scale, int thickness) {
  int baseline = 0;
  const cv::Size s = TextSize(text, scale, thickness, &baseline);
  cv::Mat patch(s.height + baseline + 4, s.width + 4, img.type(), kWhite);
  cv::putText(patch, text, cv::Point(2, s.height + 2), kFont, scale, kBlack,
              thickness, cv::LINE_AA);
  cv::Mat rotated;
  cv::rotate(patch, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect roi(center.x - rotated.cols / 2, center.y - rotated.rows / 2,
               rotated.cols, rotated.rows);
  roi &= cv::Rect(0, 0, img.cols, img.rows);
  if (roi.width <= 0 || roi.height <= 0) return;
  cv::Mat dst = img(roi);
  cv::Mat src = rotated(cv::Rect(0, 0, roi.width, roi.height));
  cv::min(dst, src, dst);  // Dark text over the light background.
}

}  // namespace slam::plot
