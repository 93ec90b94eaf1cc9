// Settings of `slam run` (2D laser SLAM on a CARMEN log): a plain struct with
// defaults, loaded from the `run:` section of a YAML file (unknown keys are
// errors) and printable back as YAML (--dump_config). See configs/aces.yaml
// and frontends/laser/laser_slam.h for what each setting does.
//
//   run:
//     log: laser_logs_carmen/aces.clf.bz2   # relative to the datasets dir
//     relations: laser_logs_carmen/aces.relations  # optional ("" = none)
//     output_dir: out/aces                  # relative to the working dir
//     lasers: {front: true, rear: false, robot: true}
//     scans: {min_range, max_range, voxel_size}
//     keyframes: {distance, rotation}
//     tracking: {submap_keyframes, submap_voxel, normal_radius, min_fitness,
//                max_jump, icp: {...}, correlative: {...}}
//     odometry: {alpha1, alpha2, alpha3, alpha4, min_sigma_xy,
//                min_sigma_theta}
//     loop_closure: {enabled, min_separation, search_radius, radius_growth,
//                    max_radius, max_candidates, submap_half_width,
//                    min_score, min_fitness, kernel, reject_weight,
//                    correlative: {...}}
//     backend: {optimize_every, loop_optimize_interval,
//               incremental_iterations, max_iterations}
//     map: {enabled, resolution, l_occ, l_free, l_min, l_max,
//           max_usable_range, clear_max_range}
//                               (frontends/laser/occupancy_grid.h)
//   icp: {max_correspondence_distance, max_iterations, huber_width,
//         inlier_distance, sigma_min, covariance_scale}
//   correlative: {resolution, coarse_factor, sigma, window_xy,
//                 window_theta, step_theta}
#ifndef SLAM_APPS_RUN_CONFIG_H_
#define SLAM_APPS_RUN_CONFIG_H_

#include <string>

#include "datasets/carmen_io.h"
#include "frontends/laser/laser_slam.h"
#include "frontends/laser/occupancy_grid.h"

namespace slam {

struct RunConfig {
  // Which pipeline `slam run` runs: "laser" (this config) or "stereo"
  // (apps/visual/stereo_run_config.h, read by slam-visual).
  std::string pipeline = "laser";
  std::string log;
  std::string relations;
  std::string output_dir = "out";
  CarmenReadOptions lasers;
  LaserSlamConfig slam;
  bool write_map = true;
  OccupancyGridConfig map;
};

bool LoadRunConfig(const std::string& path, RunConfig* config,
                   std::string* error);
bool ValidateRunConfig(const RunConfig& config, std::string* error);
std::string RunConfigToYaml(const RunConfig& config);

// A data path of a `slam run` config: absolute paths as they are; relative
// ones under --datasets, else $SLAM_DATASETS, else ../shared/datasets beside
// the repository holding the config file, else ../shared/datasets from the
// working directory (the first where it exists).
std::string ResolveDatasetPath(const std::string& path);

}  // namespace slam

#endif  // SLAM_APPS_RUN_CONFIG_H_
