// The map plot (apps/map_plot.h): trajectory and landmarks from above.
#include "apps/map_plot.h"

#include <algorithm>

#include "apps/format.h"
#include "apps/plot/plot.h"

namespace slam {

bool WriteMapPlotImpl(const std::string& path, const MapPlotData& data,
                      std::string* error) {
  plot::Axes axes;
  axes.title = data.title;
  axes.xlabel = data.xlabel;
  axes.ylabel = data.ylabel;
  axes.equal_aspect = true;
  const size_t n = data.landmark_x.size();
  // Small dots for dense maps, so that the trajectory stays visible.
  const int radius = n > 2000 ? 1 : (n > 300 ? 2 : 4);
  for (size_t k = 0; k < n; ++k) {
    plot::Marker marker;
    marker.x = data.landmark_x[k];
    marker.y = data.landmark_y[k];
    marker.color = plot::kOrange;
    marker.radius = radius;
    if (k == 0) marker.label = Fmt("landmarks (%.0f)", static_cast<double>(n));
    axes.markers.push_back(marker);
  }
  plot::Line trajectory;
  trajectory.x = data.trajectory_x;
  trajectory.y = data.trajectory_y;
  trajectory.color = plot::kBlue;
  trajectory.thickness = 2;
  trajectory.label = Fmt("trajectory (%.0f poses)",
                         static_cast<double>(data.trajectory_x.size()));
  axes.lines.push_back(trajectory);
  const cv::Mat image = plot::RenderFigure({axes}, 1200, 1000);
  return plot::SavePng(path, image, error);
}

}  // namespace slam
