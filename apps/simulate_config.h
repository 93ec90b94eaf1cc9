// Settings of `slam simulate` (datasets/simulator.h's SimulationConfig) in
// YAML: the `simulate:` section of a config file, one sub-section per part of
// the simulation, so that later parts (landmarks, IMU) add their own.
//
//   simulate:
//     seed: 1
//     world:
//       type: grid2d            # grid2d | grid3d | sphere3d | inertial
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
//     inertial:                 # world type inertial (IMU + position fixes)
//       duration: 60.0          # [s]
//       imu_rate: 200.0         # [Hz]
//       position_rate: 1.0      # [Hz], 0: no fixes
//       position_sigma: 0.1     # [m] per axis
//       lever_arm: [0, 0, 0]    # antenna in the body frame [m]
//       gravity: [0, 0, -9.81]
//       gyro_noise_density: 1.6968e-4   # ADIS16448 (EuRoC) defaults
//       accel_noise_density: 2.0e-3
//       gyro_random_walk: 1.9393e-5
//       accel_random_walk: 3.0e-3
//       initial_gyro_bias: [0.002, -0.001, 0.0015]
//       initial_accel_bias: [0.03, -0.02, 0.05]
//       trajectory_file: ""     # spline through a recorded trajectory
//       trajectory_times_file: ""  # (KITTI: its times file)
//       trajectory_y_down: false   # the file's world has y down (KITTI)
//       trajectory:             # datasets/inertial_trajectory.h
//         center: [0, 0, 2]
//         amplitude: [10, 5, 1]
//         frequency: [0.25, 0.5, 0.3]
//         ...                   # phase, yaw_*, pitch_*, roll_*
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
