// Entry points of the plot module (libslam_plot.so), looked up by name by
// apps/plot_module.cc.
#include <string>
#include <vector>

#include "apps/eval_report.h"
#include "apps/map_plot.h"
#include "apps/plot/map_plot.h"
#include "datasets/atomic_file.h"

// The output stage of the calling thread (datasets/atomic_file.h), set before
// every call into the module (apps/plot_module.cc).
extern "C" void SlamSetOutputStage(slam::OutputStage* stage) {
  slam::OutputStage::SetCurrent(stage);
}

// The module's entry point, looked up by name (apps/plot_module.h).
extern "C" bool SlamWriteEvalPlots(const std::string& dir,
                                   const slam::EvalResult& result,
                                   const slam::EvalSettings& settings,
                                   const slam::EvalLabels& labels,
                                   std::vector<std::string>* written,
                                   std::string* error) {
  return slam::WriteEvalPlotsImpl(dir, result, settings, labels, written,
                                  error);
}

// The occupancy-grid map with the trajectory (apps/map_png.h).
extern "C" bool SlamWriteMapPng(const std::string& path,
                                const slam::MapImage& image,
                                const std::vector<Eigen::Vector2d>& trajectory,
                                std::string* error) {
  return slam::WriteMapPngImpl(path, image, trajectory, error);
}

// The map plot of `slam optimize --plot` on graphs with landmarks.
extern "C" bool SlamWriteMapPlot(const std::string& path,
                                 const slam::MapPlotData& data,
                                 std::string* error) {
  return slam::WriteMapPlotImpl(path, data, error);
}
