#include "apps/map_png.h"

#include "apps/plot_module.h"

namespace slam {

bool WriteMapPng(const std::string& path, const MapImage& image,
                 const std::vector<Eigen::Vector2d>& trajectory,
                 std::string* error) {
  using Function = bool (*)(const std::string&, const MapImage&,
                            const std::vector<Eigen::Vector2d>&, std::string*);
  void* symbol = nullptr;
  if (!LoadPlotModuleSymbol("SlamWriteMapPng", &symbol, error)) return false;
  return reinterpret_cast<Function>(symbol)(path, image, trajectory, error);
}

}  // namespace slam
