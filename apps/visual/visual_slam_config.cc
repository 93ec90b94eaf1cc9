#include "apps/visual/visual_slam_config.h"

namespace slam {

using namespace config_schema;  // NOLINT: the schema vocabulary.

std::vector<Field> OrbFeatureFields(StereoFeatureConfig* f) {
  return {I("max_features", &f->max_features),
          D("scale_factor", &f->scale_factor),
          I("levels", &f->levels),
          I("fast_threshold", &f->fast_threshold),
          I("cell_size", &f->cell_size),
          I("max_per_cell", &f->max_per_cell),
          B("grid_fast", &f->grid_fast),
          I("min_fast_threshold", &f->min_fast_threshold)};
}

std::vector<Section> VisualSlamSections(StereoOdometryConfig* o,
                                        StereoLoopClosingConfig* l) {
  return {{"tracking",
           {D("pixel_sigma", &o->pixel_sigma),
            D("disparity_sigma", &o->disparity_sigma),
            D("chi2_stereo", &o->chi2_stereo),
            D("chi2_mono", &o->chi2_mono),
            D("close_depth_baselines", &o->close_depth_baselines),
            I("far_point_min_keyframes", &o->far_point_min_keyframes),
            B("far_points_wait", &o->far_points_wait),
            D("min_parallax", &o->min_parallax),
            I("local_map_keyframes", &o->local_map_keyframes),
            D("search_radius", &o->search_radius),
            I("max_descriptor_distance", &o->max_descriptor_distance),
            D("match_ratio", &o->match_ratio),
            I("pose_rounds", &o->pose_rounds),
            I("pose_iterations", &o->pose_iterations),
            I("min_inliers", &o->min_inliers),
            B("refine_with_structure", &o->refine_with_structure),
            B("track_last_frame", &o->track_last_frame),
            B("keyframe_odometry", &o->keyframe_odometry),
            D("pnp_reprojection_error", &o->pnp_reprojection_error),
            I("pnp_iterations", &o->pnp_iterations),
            D("pnp_ratio", &o->pnp_ratio)},
           {}},
          {"keyframes",
           {D("tracked_ratio", &o->keyframe_tracked_ratio),
            I("close_tracked", &o->keyframe_close_tracked),
            I("new_close", &o->keyframe_new_close),
            D("rotation", &o->keyframe_rotation),
            I("min_frames", &o->keyframe_min_frames),
            I("max_frames", &o->keyframe_max_frames),
            B("interpolate_between", &o->interpolate_between_keyframes),
            D("between_acceleration_sigma", &o->between_acceleration_sigma),
            I("min_initial_points", &o->min_initial_points),
            I("min_point_observations", &o->min_point_observations),
            I("cull_after_keyframes", &o->cull_after_keyframes)},
           {}},
          {"bundle_adjustment",
           {I("window_keyframes", &o->window_keyframes),
            I("local_iterations", &o->local_ba_iterations),
            I("final_iterations", &o->final_ba_iterations),
            B("local_mapping_thread", &o->local_mapping_thread)},
           {}},
          {"loop_closure",
           {B("enabled", &l->enabled),
            D("drift_translation", &l->drift_translation),
            D("min_sigma_translation", &l->min_sigma_translation),
            D("drift_rotation", &l->drift_rotation),
            D("min_sigma_rotation", &l->min_sigma_rotation),
            D("drift_translation_per_rad", &l->drift_translation_per_rad),
            D("drift_rotation_per_rad", &l->drift_rotation_per_rad),
            K("kernel", &l->kernel), D("reject_chi2", &l->reject_chi2),
            I("max_iterations", &l->max_iterations)},
           {}}};
}

bool LoadVisualSlamExtras(const std::string& path,
                          const StereoFeatureConfig& features,
                          StereoOdometryConfig* odometry, LoopsConfig* loops,
                          std::string* error) {
  if (!LoadLoopsConfig(path, loops, error)) return false;
  // Keyframes are verified by PnP on their points with depth (the
  // loops.verification setting is for image sequences without depth).
  loops->detector.verification = bow::Verification::kStereoPnp;
  // The pyramid scale of the features sets the noise model's scale.
  odometry->scale_factor = features.scale_factor;
  return true;
}

bool ValidateVisualSlamSettings(const StereoOdometryConfig& odometry,
                                const StereoLoopClosingConfig& loop_closure,
                                const LoopsConfig& loops, std::string* error) {
  return ValidateStereoOdometryConfig(odometry, error) &&
         ValidateStereoLoopClosingConfig(loop_closure, error) &&
         ValidateLoopsConfig(loops, error);
}

}  // namespace slam
