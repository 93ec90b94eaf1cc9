// Writes the occupancy-grid map as a PNG with the trajectory drawn on it,
// through the plot module (apps/plot/map_plot.h), so that only that module
// links OpenCV.
#ifndef SLAM_APPS_MAP_PNG_H_
#define SLAM_APPS_MAP_PNG_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "frontends/occupancy_grid.h"

namespace slam {

// False with "PATH: problem" (or the module's load error).
bool WriteMapPng(const std::string& path, const MapImage& image,
                 const std::vector<Eigen::Vector2d>& trajectory,
                 std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_MAP_PNG_H_
