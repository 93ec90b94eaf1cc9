// Settings of `slam simulate` (datasets/simulator.h's SimulationConfig) in
// YAML: the `simulate:` section of a config file, one sub-section per part of
// the simulation, so that later parts (landmarks, IMU) add their own.
//
//   simulate:
//     seed: 1
//     world:
//       type: grid2d            # grid2d | grid3d | sphere3d
//       num_poses: 500
//       step: 1.0               # grid worlds: lattice spacing [m]
//       grid_size: 10           # grid worlds: lattice points per side
//       turn_probability: 0.3   # grid worlds: chance to turn at a move
//       poses_per_ring: 50      # sphere3d: poses per revolution
//       radius: 20.0            # sphere3d: sphere radius [m]
//     odometry:
//       sigma_translation: 0.05 # [m] per axis
//       sigma_rotation: 0.01    # [rad] full angle, per axis
//     loop_closures:
//       sigma_translation: 0.05
//       sigma_rotation: 0.01
//       radius: 0.5             # grid worlds: revisit distance [m]
//       probability: 0.5        # chance that a pose closes its loops
//       max_per_pose: 1         # grid worlds
//       min_index_gap: 5        # no closures to the last few poses
//       outlier_fraction: 0.0   # share of wrong loop closures
//       outlier_max_translation: 10.0  # [m]
//
// Every key is optional (missing keys keep their current value); unknown
// keys and values of the wrong type are errors naming the file and line.
#ifndef SLAM_APPS_SIMULATE_CONFIG_H_
#define SLAM_APPS_SIMULATE_CONFIG_H_

#include <string>

#include <yaml-cpp/yaml.h>

#include "datasets/simulator.h"

namespace slam {

// Reads the `simulate:` section of `root` over *config; `where` (the file
// name) prefixes error messages. Does not validate ranges (see
// ValidateSimulationConfig).
bool SimulationConfigFromYaml(const YAML::Node& root, const std::string& where,
                              SimulationConfig* config, std::string* error);

// Loads the YAML file at `path` over *config and validates the result.
bool LoadSimulationConfig(const std::string& path, SimulationConfig* config,
                          std::string* error);

// The config as YAML (the `simulate:` section, commented), such that loading
// it gives back the same config exactly (doubles are printed in their
// shortest round-trip form).
std::string SimulationConfigToYaml(const SimulationConfig& config);

}  // namespace slam

#endif  // SLAM_APPS_SIMULATE_CONFIG_H_
