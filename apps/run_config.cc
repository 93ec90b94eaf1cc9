#include "apps/run_config.h"

#include <sstream>
#include <vector>

#include "apps/config_schema.h"
#include "apps/yaml_config.h"

namespace slam {
namespace {

using namespace config_schema;  // NOLINT: the schema vocabulary.

Section IcpSection(IcpOptions* o) {
  return {
      "icp",
      {D("max_correspondence_distance", &o->max_correspondence_distance),
       I("max_iterations", &o->max_iterations),
       D("max_step_translation", &o->max_step_translation),
       D("max_step_rotation", &o->max_step_rotation),
       D("huber_width", &o->huber_width),
       D("inlier_distance", &o->inlier_distance), D("sigma_min", &o->sigma_min),
       D("covariance_scale", &o->covariance_scale)},
      {}};
}

Section CorrelativeSection(CorrelativeOptions* o) {
  return {"correlative",
          {D("resolution", &o->resolution), I("levels", &o->levels),
           D("sigma", &o->sigma), D("window_xy", &o->window_xy),
           D("window_theta", &o->window_theta), D("step_theta", &o->step_theta),
           D("max_evaluations", &o->max_evaluations)},
          {}};
}

Section Schema(RunConfig* c) {
  LaserSlamConfig& s = c->slam;
  return {
      "run",
      {S("pipeline", &c->pipeline), S("log", &c->log),
       S("relations", &c->relations), S("output_dir", &c->output_dir)},
      {{"lasers",
        {B("front", &c->lasers.front_laser), B("rear", &c->lasers.rear_laser),
         B("robot", &c->lasers.robot_laser)},
        {}},
       {"scans",
        {D("min_range", &s.min_range), D("max_range", &s.max_range),
         D("voxel_size", &s.voxel_size)},
        {}},
       {"keyframes",
        {D("distance", &s.keyframe_distance),
         D("rotation", &s.keyframe_rotation)},
        {}},
       {"tracking",
        {I("submap_keyframes", &s.submap_keyframes),
         D("submap_voxel", &s.submap_voxel),
         D("normal_radius", &s.normal_radius),
         D("min_fitness", &s.min_tracking_fitness),
         D("max_jump", &s.max_tracking_jump),
         D("odometry_weight", &s.tracking_odometry_weight),
         I("chain_links", &s.chain_links),
         B("always_correlative", &s.always_correlative),
         B("robust", &s.robust_tracking),
         D("recheck_ratio", &s.tracking_recheck_ratio),
         D("recheck_margin", &s.tracking_recheck_margin),
         D("odometry_break_chi2", &s.odometry_break_chi2),
         D("odometry_break_inflation", &s.odometry_break_inflation),
         D("min_sigma_xy", &s.match_min_sigma_xy),
         D("min_sigma_theta", &s.match_min_sigma_theta)},
        {IcpSection(&s.icp), CorrelativeSection(&s.local_correlative)}},
       {"odometry",
        {D("alpha1", &s.odometry.alpha1), D("alpha2", &s.odometry.alpha2),
         D("alpha3", &s.odometry.alpha3), D("alpha4", &s.odometry.alpha4),
         D("min_sigma_xy", &s.odometry.min_sigma_xy),
         D("min_sigma_theta", &s.odometry.min_sigma_theta)},
        {}},
       {"loop_closure",
        {B("enabled", &s.loop_closure),
         D("min_separation", &s.loop_min_separation),
         D("search_radius", &s.loop_search_radius),
         D("radius_growth", &s.loop_radius_growth),
         D("max_radius", &s.loop_max_radius),
         I("max_candidates", &s.loop_max_candidates),
         I("submap_half_width", &s.loop_submap_half_width),
         I("query_keyframes", &s.loop_query_keyframes),
         D("query_voxel", &s.loop_query_voxel),
         D("search_voxel", &s.loop_search_voxel),
         D("min_score", &s.loop_min_score),
         I("every", &s.loop_every),
         I("place_max_closures", &s.loop_place_max_closures),
         D("anchored_path", &s.loop_anchored_path),
         D("optimize_min_correction", &s.loop_optimize_min_correction),
         B("seeded_verification", &s.loop_seeded_verification),
         I("search_verifications", &s.loop_search_verifications),
         I("min_inliers", &s.loop_min_inliers),
         D("min_fitness", &s.loop_min_fitness),
         D("max_sigma", &s.loop_max_sigma),
         D("min_inlier_ratio", &s.loop_min_inlier_ratio),
         I("consistency_keyframes", &s.loop_consistency_keyframes),
         D("consistency_distance", &s.loop_consistency_distance),
         D("consistency_angle", &s.loop_consistency_angle),
         K("kernel", &s.loop_kernel),
         D("reject_weight", &s.loop_reject_weight),
         B("final_pass", &s.loop_final_pass),
         D("final_radius", &s.loop_final_radius),
         D("final_max_correction", &s.loop_final_max_correction),
         B("global", &s.loop_global),
         D("global_min_path", &s.loop_global_min_path),
         I("global_every", &s.loop_global_every),
         I("global_preselect", &s.loop_global_preselect),
         I("global_candidates", &s.loop_global_candidates),
         D("global_max_distance", &s.loop_global_max_distance),
         D("global_window", &s.loop_global_window),
         D("global_probe_evaluations", &s.loop_global_probe_evaluations),
         I("global_min_agreeing", &s.loop_global_min_agreeing),
         D("global_max_chi2", &s.loop_global_max_chi2),
         D("max_chi2_per_link", &s.loop_max_chi2_per_link),
         I("undone_memory", &s.loop_undone_memory),
         I("context_rings", &s.loop_context.rings),
         I("context_sectors", &s.loop_context.sectors),
         D("context_range", &s.loop_context.max_range),
         I("context_key_harmonics", &s.loop_context.key_harmonics)},
        {CorrelativeSection(&s.loop_correlative)}},
       {"backend",
        {I("optimize_every", &s.optimize_every),
         I("loop_optimize_interval", &s.loop_optimize_interval),
         I("incremental_iterations", &s.incremental_iterations),
         I("max_iterations", &s.optimizer.max_iterations)},
        {}},
       {"refine",
        {B("enabled", &s.refine_scans), I("window", &s.refine_window),
         D("radius", &s.refine_radius), D("max_jump", &s.refine_max_jump),
         B("interpolate_scans", &s.interpolate_scans)},
        {}},
       {"map",
        {B("enabled", &c->write_map), D("resolution", &c->map.resolution),
         D("l_occ", &c->map.l_occ), D("l_free", &c->map.l_free),
         D("l_min", &c->map.l_min), D("l_max", &c->map.l_max),
         D("max_usable_range", &c->map.max_usable_range),
         B("clear_max_range", &c->map.clear_max_range)},
        {}}}};
}

}  // namespace

bool LoadRunConfig(const std::string& path, RunConfig* config,
                   std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["run"];
  if (!node) return true;
  if (!LoadSection(node, Schema(config), path, error)) return false;
  if (!ValidateRunConfig(*config, error)) {
    *error = path + ": run." + *error;
    return false;
  }
  return true;
}

bool ValidateRunConfig(const RunConfig& config, std::string* error) {
  const LaserSlamConfig& s = config.slam;
  auto fail = [&](const std::string& message) {
    *error = message;
    return false;
  };
  if (!(s.min_range >= 0) || !(s.max_range > s.min_range)) {
    return fail("scans: need 0 <= min_range < max_range");
  }
  if (!(s.voxel_size > 0) || !(s.submap_voxel > 0) || !(s.normal_radius > 0)) {
    return fail("voxel sizes and normal_radius must be > 0");
  }
  if (!(s.keyframe_distance > 0) || !(s.keyframe_rotation > 0)) {
    return fail("keyframes: distance and rotation must be > 0");
  }
  if (s.submap_keyframes < 1)
    return fail("tracking.submap_keyframes must be >= 1");
  for (const IcpOptions* o : {&s.icp}) {
    if (!(o->max_correspondence_distance > 0) || o->max_iterations < 1 ||
        !(o->huber_width > 0) || !(o->inlier_distance > 0) ||
        !(o->sigma_min > 0) || !(o->covariance_scale > 0)) {
      return fail(
          "tracking.icp: distances, widths and scales must be > 0, "
          "max_iterations >= 1");
    }
  }
  for (const CorrelativeOptions* o :
       {&s.local_correlative, &s.loop_correlative}) {
    if (!(o->resolution > 0) || o->levels < 0 || o->levels > 12 ||
        !(o->sigma > 0) || !(o->window_xy >= 0) || !(o->window_theta >= 0) ||
        !(o->step_theta > 0)) {
      return fail(
          "correlative: resolution, sigma, step_theta must be > 0, "
          "windows >= 0, levels in [0, 12]");
    }
    if ((2.0 * o->window_xy / o->resolution + 1) *
            (2.0 * o->window_theta / o->step_theta + 1) >
        5e7) {
      return fail("correlative: search window too large for its resolution");
    }
  }
  const OdometryNoise& n = s.odometry;
  if (!(n.alpha1 >= 0) || !(n.alpha2 >= 0) || !(n.alpha3 >= 0) ||
      !(n.alpha4 >= 0) || !(n.min_sigma_xy > 0) || !(n.min_sigma_theta > 0)) {
    return fail("odometry: alphas must be >= 0, minimum sigmas > 0");
  }
  if (s.loop_max_candidates < 0 || s.loop_submap_half_width < 0 ||
      !(s.loop_search_radius >= 0) || !(s.loop_max_radius >= 0) ||
      !(s.loop_radius_growth >= 0) || !(s.loop_min_separation >= 0)) {
    return fail("loop_closure: counts, radii and separation must be >= 0");
  }
  if (s.optimize_every < 0 || s.loop_optimize_interval < 0 ||
      s.incremental_iterations < 1 || s.optimizer.max_iterations < 1) {
    return fail("backend: intervals must be >= 0, iterations >= 1");
  }
  std::string map_error;
  if (!CheckOccupancyGridConfig(config.map, &map_error)) {
    return fail("map: " + map_error);
  }
  if (!config.lasers.front_laser && !config.lasers.rear_laser &&
      !config.lasers.robot_laser) {
    return fail("lasers: select at least one laser");
  }
  return true;
}

std::string RunConfigToYaml(const RunConfig& config) {
  RunConfig copy = config;
  std::ostringstream out;
  out.precision(10);
  PrintSection(Schema(&copy), 0, &out);
  return out.str();
}

}  // namespace slam
