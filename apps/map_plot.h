// The map plot of `slam optimize --plot DIR` on graphs with landmarks: the
// trajectory (pose positions in id order) and the landmarks, seen from above
// (2D graphs: x, y; 3D graphs: the two world axes along which the trajectory
// extends most), equal aspect, written as DIR/map.png by the plot module
// (apps/plot_module.h, entry point SlamWriteMapPlot).
#ifndef SLAM_APPS_MAP_PLOT_H_
#define SLAM_APPS_MAP_PLOT_H_

#include <string>
#include <vector>

#include "core/graph.h"

namespace slam {

struct MapPlotData {
  std::string title;
  std::string xlabel;
  std::string ylabel;
  std::vector<double> trajectory_x, trajectory_y;
  std::vector<double> landmark_x, landmark_y;
};

// The plot data of a graph (pose and point nodes).
MapPlotData MapPlotFromGraph(const Graph& graph, const std::string& title);

// Draws it to `path` (PNG) through the plot module.
bool WriteMapPlot(const std::string& path, const MapPlotData& data,
                  std::string* error);

// Implemented in the plot module (apps/plot/map_plot.cc).
bool WriteMapPlotImpl(const std::string& path, const MapPlotData& data,
                      std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_MAP_PLOT_H_
