// Loading the plot module. Drawing uses OpenCV, whose shared libraries cost
// about 9 ms of dynamic loading at every process start; the pose-graph
// benchmarks count whole-process wall time, and most runs draw nothing. So
// the drawing code lives in a separate module, libslam_plot.so (apps/plot/),
// that is loaded with dlopen the first time a plot is written.
//
// The module is looked up, in order: $SLAM_PLOT_MODULE, beside the running
// executable, and at the path where the build put it.
#ifndef SLAM_APPS_PLOT_MODULE_H_
#define SLAM_APPS_PLOT_MODULE_H_

#include <string>

namespace slam {

// Loads the module (once) and finds `name` in it; false with a message
// naming the paths tried.
bool LoadPlotModuleSymbol(const char* name, void** symbol, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_PLOT_MODULE_H_
