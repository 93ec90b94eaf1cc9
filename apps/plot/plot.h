// A small plotting module for the evaluation reports: line plots with axes,
// tick labels, grid, title, legend, horizontal reference lines, and paths
// colour-coded by a value with a colour bar. Rendered with OpenCV
// (core, imgproc) and written as PNG (zlib, see EncodePng), atomically.
#ifndef SLAM_APPS_PLOT_H_
#define SLAM_APPS_PLOT_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace slam::plot {

// Colours (BGR, as OpenCV).
const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kGray(140, 140, 140);
const cv::Scalar kBlue(180, 110, 31);     // Matplotlib C0.
const cv::Scalar kOrange(14, 127, 255);   // C1.
const cv::Scalar kGreen(44, 160, 44);     // C2.
const cv::Scalar kRed(40, 39, 214);       // C3.
const cv::Scalar kPurple(189, 103, 148);  // C4.

struct Line {
  std::vector<double> x;
  std::vector<double> y;
  cv::Scalar color = kBlue;
  int thickness = 2;
  bool dashed = false;
  std::string label;  // Empty: not in the legend.
};

// A path whose segments take the colour of `value` on a colour map.
struct ColoredPath {
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> value;
  double vmin = 0.0;
  double vmax = 1.0;
  std::string colorbar_label;
  std::string label;
  int thickness = 3;
};

struct HLine {
  double y = 0.0;
  cv::Scalar color = kRed;
  bool dashed = true;
  std::string label;
};

struct Marker {
  double x = 0.0;
  double y = 0.0;
  cv::Scalar color = kBlack;
  bool square = false;  // Else a circle.
  std::string label;
  int radius = 7;  // Pixels (half the square's side).
};

struct Axes {
  std::string title;
  std::string xlabel;
  std::string ylabel;
  bool equal_aspect = false;  // Same metres per pixel on both axes.
  std::vector<Line> lines;
  std::vector<ColoredPath> paths;  // At most one gets a colour bar.
  std::vector<HLine> hlines;
  std::vector<Marker> markers;
};

// Renders `panels` stacked vertically, each width x panel_height pixels.
cv::Mat RenderFigure(const std::vector<Axes>& panels, int width,
                     int panel_height);

// PNG bytes of an 8-bit BGR image (RGB, 8 bit, filter none, zlib); false for
// another image type. Written here with zlib so that the binary does not
// load OpenCV's imgcodecs (over a hundred shared libraries at start-up).
bool EncodePng(const cv::Mat& image, std::string* png);
// Writes a PNG atomically; false with "PATH: problem".
bool SavePng(const std::string& path, const cv::Mat& image, std::string* error);

// "Nice" tick positions (steps of 1, 2 or 5 times a power of ten) covering
// [lo, hi] with about `target` ticks; *step receives the step.
std::vector<double> NiceTicks(double lo, double hi, int target, double* step);
// A tick label with as many decimals as the step needs.
std::string FormatTick(double value, double step);

// The colour of t in [0, 1] on the colour map used for paths (jet).
cv::Scalar ColorMap(double t);

}  // namespace slam::plot

#endif  // SLAM_APPS_PLOT_H_
