// Settings of `slam inertial`: a plain struct with defaults, loaded from the
// `inertial:` section of a YAML file and printable back as YAML.
//
//   inertial:
//     input_format: auto       # auto | euroc | gtsam
//     initial_state: auto      # auto | ground_truth (see below)
//     estimator: both          # window | batch | both
//     keyframe_rate: 10        # Hz
//     window_size: 10          # keyframes
//     window_iterations: 10    # Ceres iterations per update
//     linear_solver: sparse_normal_cholesky  # or dense_normal_cholesky, ...
//     gravity: auto            # auto (the input's) or [gx, gy, gz]
//     gyro_noise_density: 1.6968e-4   # rad/s/sqrt(Hz)   (ADIS16448)
//     accel_noise_density: 2.0e-3     # m/s^2/sqrt(Hz)
//     gyro_random_walk: 1.9393e-5     # rad/s^2/sqrt(Hz)
//     accel_random_walk: 3.0e-3       # m/s^3/sqrt(Hz)
//     gyro_noise_inflation: 1    # multipliers of the two white-noise
//     accel_noise_inflation: 1   #   densities above (see below)
//     position_sigma: 0.1      # m, position fixes
//     lever_arm: [0, 0, 0]     # fix antenna in the body frame, m
//     prior_position_sigma: 0.01   # initial state prior (when the input
//     prior_rotation_sigma: 0.01   #   has an initial state), m, rad,
//     prior_velocity_sigma: 0.1    #   m/s
//     prior_gyro_bias_sigma: 0.01  # rad/s, sigma of the first bias prior
//     prior_accel_bias_sigma: 0.1  # m/s^2
//     moving_start_gyro_bias_sigma: 0.01  # rad/s, gyro bias prior of a
//                                   # start in motion (turn-on bias)
//     initial_gyro_bias: [0, 0, 0]   # rad/s, mean of the first bias prior
//     initial_accel_bias: [0, 0, 0]  # m/s^2
//
// initial_state: auto uses the input's initial state when it has one (the
// GTSAM "i" row), else the initializer's (still start and in-motion
// alignment, frontends/inertial/inertial_initializer.h); ground_truth starts
// at the first ground-truth state of an EuRoC folder (IMU readings before it
// are dropped) with the prior sigmas above, as EuRoC evaluations commonly do;
// it takes the ground truth's bias as the prior mean too (in place of
// initial_*_bias).
// Noise: the densities default to the EuRoC sensor's data sheet (ADIS16448
// as EuRoC's imu0/sensor.yaml states it), which the simulator generates.
// On a flying platform rotor vibration and unmodelled effects (aliasing,
// scale/misalignment) add white noise the data sheet, measured at rest, does
// not have: gyro_noise_inflation / accel_noise_inflation multiply the two
// white-noise densities (the random walks stay) so that the data sheet
// values stay visible in the config. configs/inertial_euroc.yaml sets them for
// the EuRoC MAV (16 and 8: measured noise and NEES in README.md, "Inertial
// estimation").
// For the GTSAM example file use gyro/accel densities 2.05689e-4 / 3.924e-4,
// random walks 1.454441e-6 / 4.905e-3, position_sigma 1.0, and a wide
// prior_velocity_sigma (its initial velocity row is not consistent with the
// data, see datasets/imu_io.h); configs/inertial_gtsam.yaml holds them.
#ifndef SLAM_APPS_INERTIAL_CONFIG_H_
#define SLAM_APPS_INERTIAL_CONFIG_H_

#include <string>

#include "frontends/inertial/inertial_estimator.h"

namespace slam {

struct InertialConfig {
  std::string input_format = "auto";
  std::string initial_state = "auto";
  std::string estimator = "both";
  bool gravity_auto = true;
  // Multipliers of options.noise's white-noise densities (>= 1 expected;
  // any value > 0 accepted), applied by EffectiveInertialOptions.
  double gyro_noise_inflation = 1.0;
  double accel_noise_inflation = 1.0;
  InertialOptions options;  // keyframe rate, noise, priors, window options.
};

// Reads the `inertial:` section of the YAML file at `path` over *config.
// Unknown keys and bad values are errors naming the file.
bool LoadInertialConfig(const std::string& path, InertialConfig* config,
                        std::string* error);
bool ValidateInertialConfig(const InertialConfig& config, std::string* error);
std::string InertialConfigToYaml(const InertialConfig& config);
// config.options with the noise inflation applied to the densities.
InertialOptions EffectiveInertialOptions(const InertialConfig& config);

}  // namespace slam

#endif  // SLAM_APPS_INERTIAL_CONFIG_H_
