// Entry points of the plot module (libslam_plot.so), looked up by name by
// apps/plot_module.cc.
#include <string>
#include <vector>

#include "apps/eval_report.h"

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
