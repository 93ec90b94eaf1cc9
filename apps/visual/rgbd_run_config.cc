#include "apps/visual/rgbd_run_config.h"

#include <sstream>

#include "apps/config_schema.h"
#include "apps/visual/visual_slam_config.h"
#include "apps/yaml_config.h"

namespace slam {
namespace {

using namespace config_schema;  // NOLINT: the schema vocabulary.

Section Schema(RgbdRunConfig* c) {
  RgbdCamera& k = c->intrinsics;
  RgbdConfig& d = c->depth;
  Section run{
      "run",
      {S("pipeline", &c->pipeline), S("sequence", &c->sequence),
       S("ground_truth", &c->ground_truth), S("output_dir", &c->output_dir),
       I("max_frames", &c->max_frames),
       D("max_time_difference", &c->max_time_difference),
       S("camera", &c->camera), B("fixed_rate_capture", &d.fixed_rate_capture)},
      {{"intrinsics",
        {D("fx", &k.fx), D("fy", &k.fy), D("cx", &k.cx), D("cy", &k.cy),
         D("k1", &k.k1), D("k2", &k.k2), D("p1", &k.p1), D("p2", &k.p2),
         D("k3", &k.k3)},
        {}},
       {"depth",
        {D("depth_factor", &d.depth_factor),
         D("virtual_baseline", &d.virtual_baseline),
         D("min_depth", &d.min_depth), D("max_depth", &d.max_depth),
         I("depth_radius", &d.depth_radius),
         D("max_depth_step", &d.max_depth_step)},
        {}},
       {"features", OrbFeatureFields(&c->features), {}}}};
  for (Section& s :
       VisualSlamSections(&c->slam.odometry, &c->slam.loop_closure)) {
    run.children.push_back(std::move(s));
  }
  return run;
}

}  // namespace

bool LoadRgbdRunConfig(const std::string& path, RgbdRunConfig* config,
                       std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["run"];
  if (node && !LoadSection(node, Schema(config), path, error)) return false;
  if (!LoadVisualSlamExtras(path, config->features, &config->slam.odometry,
                            &config->slam.loops, error)) {
    return false;
  }
  if (!ValidateRgbdRunConfig(*config, error)) {
    *error = path + ": run." + *error;
    return false;
  }
  return true;
}

bool ValidateRgbdRunConfig(const RgbdRunConfig& config, std::string* error) {
  if (config.pipeline != "rgbd") {
    *error = "pipeline must be 'rgbd' here";
    return false;
  }
  if (config.max_frames < 0) {
    *error = "max_frames must be >= 0 (0: all)";
    return false;
  }
  if (!(config.max_time_difference > 0 && config.max_time_difference < 1)) {
    *error = "max_time_difference must be in (0, 1) s";
    return false;
  }
  RgbdCamera preset;
  if (config.camera != "auto" && config.camera != "custom" &&
      !TumCameraPreset(config.camera, &preset)) {
    *error = "camera must be freiburg1, freiburg2, freiburg3, custom or auto";
    return false;
  }
  const RgbdCamera& k = config.intrinsics;
  if (config.camera == "custom" &&
      !(k.fx > 0 && k.fy > 0 && k.cx > 0 && k.cy > 0)) {
    *error = "intrinsics: camera custom needs fx, fy, cx, cy > 0";
    return false;
  }
  std::string problem;
  if (!ValidateRgbdConfig(config.depth, &problem)) {
    *error = "depth: " + problem;
    return false;
  }
  StereoFeatureConfig features = config.features;
  if (!ValidateStereoFeatureConfig(features, &problem)) {
    *error = "features: " + problem;
    return false;
  }
  if (!ValidateVisualSlamSettings(config.slam.odometry,
                                  config.slam.loop_closure, config.slam.loops,
                                  error)) {
    return false;
  }
  return true;
}

std::string RgbdRunConfigToYaml(const RgbdRunConfig& config) {
  RgbdRunConfig copy = config;
  std::ostringstream out;
  out.precision(10);
  PrintSection(Schema(&copy), 0, &out);
  out << LoopsConfigToYaml(copy.slam.loops);
  return out.str();
}

bool ChooseRgbdCamera(const RgbdRunConfig& config, const std::string& folder,
                      RgbdCamera* camera, std::string* how,
                      std::string* error) {
  if (config.camera == "custom") {
    *camera = config.intrinsics;
    camera->name = "custom";
    *how = "from run.intrinsics";
    return true;
  }
  if (config.camera != "auto") {
    TumCameraPreset(config.camera, camera);
    *how = "preset named by run.camera";
    return true;
  }
  const std::string guess = GuessTumCameraPreset(folder);
  if (guess.empty()) {
    *error = folder +
             ": run.camera is auto but the folder name names no Freiburg "
             "camera (freiburg1/2/3 or fr1/2/3): set run.camera to a preset "
             "or to custom with run.intrinsics";
    return false;
  }
  TumCameraPreset(guess, camera);
  *how = "guessed from the folder name";
  return true;
}

}  // namespace slam
