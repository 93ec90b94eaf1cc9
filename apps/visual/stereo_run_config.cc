#include "apps/visual/stereo_run_config.h"

#include <sstream>

#include "apps/config_schema.h"
#include "apps/visual/visual_slam_config.h"
#include "apps/yaml_config.h"

namespace slam {
namespace {

using namespace config_schema;  // NOLINT: the schema vocabulary.

Section Schema(StereoRunConfig* c) {
  StereoFeatureConfig& f = c->features;
  Section run{
      "run",
      {S("pipeline", &c->pipeline), S("sequence", &c->sequence),
       S("ground_truth", &c->ground_truth), S("output_dir", &c->output_dir),
       D("frame_period", &c->frame_period), I("max_frames", &c->max_frames),
       S("playback", &c->playback)},
      {{"features", OrbFeatureFields(&f), {}}}};
  std::vector<Field>& features = run.children[0].fields;
  for (const Field& field :
       {D("row_tolerance", &f.row_tolerance),
        D("min_disparity", &f.min_disparity),
        D("max_disparity_fraction", &f.max_disparity_fraction),
        I("max_descriptor_distance", &f.max_descriptor_distance),
        D("ratio", &f.ratio), I("patch_radius", &f.patch_radius),
        I("search_radius", &f.search_radius),
        D("max_depth_baselines", &f.max_depth_baselines)}) {
    features.push_back(field);
  }
  for (Section& s : VisualSlamSections(&c->odometry, &c->loop_closure)) {
    run.children.push_back(std::move(s));
  }
  return run;
}

}  // namespace

bool ReadRunPipeline(const std::string& path, std::string* pipeline,
                     std::string* error) {
  *pipeline = "laser";
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || !root.IsMap()) return true;
  const YAML::Node run = root["run"];
  if (!run || !run.IsMap()) return true;
  return ReadOptional(run, "pipeline", path, pipeline, error);
}

bool LoadStereoRunConfig(const std::string& path, StereoRunConfig* config,
                         std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["run"];
  if (!node) return true;
  if (!LoadSection(node, Schema(config), path, error)) return false;
  if (!LoadVisualSlamExtras(path, config->features, &config->odometry,
                            &config->loops, error)) {
    return false;
  }
  if (!ValidateStereoRunConfig(*config, error)) {
    *error = path + ": run." + *error;
    return false;
  }
  return true;
}

bool ValidateStereoRunConfig(const StereoRunConfig& config,
                             std::string* error) {
  if (config.pipeline != "stereo") {
    *error = "pipeline must be 'stereo' here";
    return false;
  }
  if (!(config.frame_period > 0 && config.frame_period < 1e3)) {
    *error = "frame_period must be in (0, 1000) s";
    return false;
  }
  if (config.playback != "forward" && config.playback != "forward_backward") {
    *error = "playback must be forward or forward_backward";
    return false;
  }
  if (config.max_frames < 0) {
    *error = "max_frames must be >= 0 (0: all)";
    return false;
  }
  std::string problem;
  if (!ValidateStereoFeatureConfig(config.features, &problem)) {
    *error = "features: " + problem;
    return false;
  }
  return ValidateVisualSlamSettings(config.odometry, config.loop_closure,
                                    config.loops, error);
}

std::string StereoRunConfigToYaml(const StereoRunConfig& config) {
  StereoRunConfig copy = config;
  std::ostringstream out;
  out.precision(10);
  PrintSection(Schema(&copy), 0, &out);
  out << LoopsConfigToYaml(copy.loops);
  return out.str();
}

}  // namespace slam
