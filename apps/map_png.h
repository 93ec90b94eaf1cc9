// Writes the occupancy-grid map as a PNG with the trajectory drawn on it,
// through the plot module (apps/plot/map_plot.h), so that only that module
// links OpenCV.
#ifndef SLAM_APPS_MAP_PNG_H_
#define SLAM_APPS_MAP_PNG_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "frontends/laser/occupancy_grid.h"

namespace slam {

// Longest side of the map picture in pixels: larger maps are drawn with
// cells merged (OccupancyGrid::ToImage(max_side), DownsampleMapImage), so
// that the picture costs the same whatever the map's extent; the PGM keeps
// the full resolution.
constexpr int kMapPngMaxSide = 4096;

// False with "PATH: problem" (or the module's load error).
bool WriteMapPng(const std::string& path, const MapImage& image,
                 const std::vector<Eigen::Vector2d>& trajectory,
                 std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_MAP_PNG_H_
