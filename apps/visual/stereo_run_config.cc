#include "apps/visual/stereo_run_config.h"

#include <sstream>

#include "apps/config_schema.h"
#include "apps/yaml_config.h"

namespace slam {
namespace {

using namespace config_schema;  // NOLINT: the schema vocabulary.

Section Schema(StereoRunConfig* c) {
  StereoFeatureConfig& f = c->features;
  StereoOdometryConfig& o = c->odometry;
  return {
      "run",
      {S("pipeline", &c->pipeline), S("sequence", &c->sequence),
       S("ground_truth", &c->ground_truth), S("output_dir", &c->output_dir),
       D("frame_period", &c->frame_period), I("max_frames", &c->max_frames),
       S("playback", &c->playback)},
      {{"features",
        {I("max_features", &f.max_features), D("scale_factor", &f.scale_factor),
         I("levels", &f.levels), I("fast_threshold", &f.fast_threshold),
         I("cell_size", &f.cell_size), I("max_per_cell", &f.max_per_cell),
         D("row_tolerance", &f.row_tolerance),
         D("min_disparity", &f.min_disparity),
         D("max_disparity_fraction", &f.max_disparity_fraction),
         I("max_descriptor_distance", &f.max_descriptor_distance),
         D("ratio", &f.ratio), I("patch_radius", &f.patch_radius),
         I("search_radius", &f.search_radius),
         D("max_depth_baselines", &f.max_depth_baselines)},
        {}},
       {"tracking",
        {D("pixel_sigma", &o.pixel_sigma), D("chi2_stereo", &o.chi2_stereo),
         D("chi2_mono", &o.chi2_mono),
         D("close_depth_baselines", &o.close_depth_baselines),
         I("far_point_min_keyframes", &o.far_point_min_keyframes),
         B("far_points_wait", &o.far_points_wait),
         D("min_parallax", &o.min_parallax),
         I("local_map_keyframes", &o.local_map_keyframes),
         D("search_radius", &o.search_radius),
         I("max_descriptor_distance", &o.max_descriptor_distance),
         D("match_ratio", &o.match_ratio), I("pose_rounds", &o.pose_rounds),
         I("pose_iterations", &o.pose_iterations),
         I("min_inliers", &o.min_inliers),
         D("pnp_reprojection_error", &o.pnp_reprojection_error),
         I("pnp_iterations", &o.pnp_iterations), D("pnp_ratio", &o.pnp_ratio)},
        {}},
       {"keyframes",
        {D("tracked_ratio", &o.keyframe_tracked_ratio),
         I("close_tracked", &o.keyframe_close_tracked),
         I("new_close", &o.keyframe_new_close),
         D("rotation", &o.keyframe_rotation),
         I("min_frames", &o.keyframe_min_frames),
         I("max_frames", &o.keyframe_max_frames),
         I("min_initial_points", &o.min_initial_points),
         I("min_point_observations", &o.min_point_observations),
         I("cull_after_keyframes", &o.cull_after_keyframes)},
        {}},
       {"bundle_adjustment",
        {I("window_keyframes", &o.window_keyframes),
         I("local_iterations", &o.local_ba_iterations),
         I("final_iterations", &o.final_ba_iterations)},
        {}},
       {"loop_closure",
        {B("enabled", &c->loop_closure.enabled),
         D("drift_translation", &c->loop_closure.drift_translation),
         D("min_sigma_translation", &c->loop_closure.min_sigma_translation),
         D("drift_rotation", &c->loop_closure.drift_rotation),
         D("min_sigma_rotation", &c->loop_closure.min_sigma_rotation),
         K("kernel", &c->loop_closure.kernel),
         D("reject_chi2", &c->loop_closure.reject_chi2),
         I("max_iterations", &c->loop_closure.max_iterations)},
        {}}}};
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
  if (!LoadLoopsConfig(path, &config->loops, error)) return false;
  // Stereo keyframes are verified by PnP on their stereo points (the
  // loops.verification setting is for image sequences without depth).
  config->loops.detector.verification = bow::Verification::kStereoPnp;
  // The pyramid scale of the features sets the noise model's scale.
  config->odometry.scale_factor = config->features.scale_factor;
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
  if (!ValidateStereoOdometryConfig(config.odometry, &problem) ||
      !ValidateStereoLoopClosingConfig(config.loop_closure, &problem) ||
      !ValidateLoopsConfig(config.loops, &problem)) {
    *error = problem;
    return false;
  }
  return true;
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
