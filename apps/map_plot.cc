#include "apps/map_plot.h"

#include <Eigen/Core>

#include "apps/plot_module.h"

namespace slam {

MapPlotData MapPlotFromGraph(const Graph& graph, const std::string& title) {
  MapPlotData data;
  data.title = title;
  std::vector<Eigen::Vector3d> poses, points;
  bool is3 = false;
  for (const auto& [key, node] : graph.nodes()) {
    const std::vector<double>& v = node->value;
    switch (key.kind) {
      case NodeKind::kPose2:
        poses.emplace_back(v[0], v[1], 0.0);
        break;
      case NodeKind::kPose3:
        poses.emplace_back(v[0], v[1], v[2]);
        is3 = true;
        break;
      case NodeKind::kPoint2:
        points.emplace_back(v[0], v[1], 0.0);
        break;
      case NodeKind::kPoint3:
        points.emplace_back(v[0], v[1], v[2]);
        break;
      default:
        break;
    }
  }
  int a = 0, b = 1;
  if (is3 && !poses.empty()) {
    Eigen::Vector3d lo = poses[0], hi = poses[0];
    for (const Eigen::Vector3d& p : poses) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d extent = hi - lo;
    int least = 0;
    extent.minCoeff(&least);
    a = least == 0 ? 1 : 0;
    b = least == 2 ? 1 : 2;
  }
  const char* names[] = {"x [m]", "y [m]", "z [m]"};
  data.xlabel = names[a];
  data.ylabel = names[b];
  for (const Eigen::Vector3d& p : poses) {
    data.trajectory_x.push_back(p[a]);
    data.trajectory_y.push_back(p[b]);
  }
  for (const Eigen::Vector3d& p : points) {
    data.landmark_x.push_back(p[a]);
    data.landmark_y.push_back(p[b]);
  }
  return data;
}

bool WriteMapPlot(const std::string& path, const MapPlotData& data,
                  std::string* error) {
  void* symbol = nullptr;
  if (!LoadPlotModuleSymbol("SlamWriteMapPlot", &symbol, error)) return false;
  using Fn = bool (*)(const std::string&, const MapPlotData&, std::string*);
  return reinterpret_cast<Fn>(symbol)(path, data, error);
}

}  // namespace slam
