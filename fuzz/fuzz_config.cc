// YAML configs of every command (unknown keys, wrong types, bad values).
// The first byte picks the loader.
#include <string>

#include "apps/eval_report.h"
#include "apps/inertial_config.h"
#include "apps/optimize_config.h"
#include "apps/run_config.h"
#include "apps/simulate_config.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string path =
      slam::fuzz::WriteScratch("config.yaml", data + 1, size - 1);
  std::string error;
  bool ok = false;
  switch (data[0] % 5) {
    case 0: {
      slam::RunConfig config;
      ok = slam::LoadRunConfig(path, &config, &error);
      break;
    }
    case 1: {
      slam::OptimizeConfig config;
      ok = slam::LoadOptimizeConfig(path, &config, &error);
      break;
    }
    case 2: {
      slam::InertialConfig config;
      ok = slam::LoadInertialConfig(path, &config, &error);
      break;
    }
    case 3: {
      slam::SimulationConfig config;
      ok = slam::LoadSimulationConfig(path, &config, &error);
      break;
    }
    case 4: {
      slam::EvalSettings settings;
      ok = slam::LoadEvalSectionOfConfig(path, &settings, &error);
      break;
    }
  }
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
