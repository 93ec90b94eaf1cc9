// The occupancy-grid map as a picture: the map_server image (black occupied,
// light free, grey unknown) with the robot's path drawn over it (blue, start
// green, end red). Part of the plot module (libslam_plot.so, see
// apps/plot_module.h); the rest of the program calls it through
// apps/map_png.h.
#ifndef SLAM_APPS_PLOT_MAP_PLOT_H_
#define SLAM_APPS_PLOT_MAP_PLOT_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "frontends/laser/occupancy_grid.h"

namespace slam {

// An 8-bit BGR image of (image.height * scale) x (image.width * scale)
// pixels; trajectory points are world (x, y) positions.
cv::Mat RenderMapImage(const MapImage& image,
                       const std::vector<Eigen::Vector2d>& trajectory,
                       int scale);

// `image` with k x k pixels merged into one (MergeMapPixels; k the smallest
// integer that keeps both sides within max_side; the resolution k times
// coarser, the same origin, blocks counted from the origin); `image` itself
// when it fits.
MapImage DownsampleMapImage(const MapImage& image, int max_side);

// Renders (scaled up to about 800 pixels for small maps, merged down to
// kMapPngMaxSide for large ones, apps/map_png.h) and writes a PNG
// atomically; false with "PATH: problem".
bool WriteMapPngImpl(const std::string& path, const MapImage& image,
                     const std::vector<Eigen::Vector2d>& trajectory,
                     std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_PLOT_MAP_PLOT_H_
