// Synthetic inertial datasets: IMU readings with white noise and random-walk
// biases, and noisy position fixes, generated from a smooth trajectory of
// datasets/inertial_trajectory.h (the built-in Lissajous figure eight with
// varying attitude, or a C2 B-spline through a recorded trajectory such as
// KITTI's ground truth), with ground truth (pose, velocity, biases) at every
// IMU sample.
//
// Sensor model (core/imu_preintegration.h conventions), at sample k, stamp
// t_k = k / imu_rate, dt = 1 / imu_rate:
//   gyro_k  = omega_B(t_k) + bg_k + sigma_g / sqrt(dt) n
//   accel_k = R(t_k)^T (a_W(t_k) - g) + ba_k + sigma_a / sqrt(dt) n
//   bg_{k+1} = bg_k + sigma_bg sqrt(dt) n,  ba_{k+1} = ba_k + sigma_ba sqrt(dt)
//   n
// with n standard normal per axis and the continuous-time densities of
// ImuNoise (datasheet units; the default is the ADIS16448 of EuRoC, from
// its sensor.yaml). Readings are samples AT the stamps (as a real IMU
// delivers them); IntegrateImuSamples (core/imu_preintegration.h)
// integrates them between keyframes to second order.
// Position fixes at t_m = m / position_rate: p(t_m) + R(t_m) lever_arm +
// position_sigma n (world frame).
// Randomness: datasets/simulation_random.h, one seed for everything.
#ifndef SLAM_DATASETS_INERTIAL_SIMULATOR_H_
#define SLAM_DATASETS_INERTIAL_SIMULATOR_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/imu_preintegration.h"
#include "datasets/imu_io.h"
#include "datasets/inertial_trajectory.h"

namespace slam {

struct InertialSimulationConfig {
  double duration = 60.0;       // [s]
  double imu_rate = 200.0;      // [Hz]
  double position_rate = 1.0;   // [Hz]; 0: no position fixes.
  double position_sigma = 0.1;  // [m] per axis.
  Eigen::Vector3d lever_arm = Eigen::Vector3d::Zero();  // Antenna, body [m].
  ImuNoise noise;  // Noise densities; zeros allowed.
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d(0.002, -0.001, 0.0015);
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d(0.03, -0.02, 0.05);
  Eigen::Vector3d gravity = DefaultGravity();
  LissajousParams trajectory;
  // Instead of the Lissajous curve: a spline (SplineTrajectory) through the
  // poses of this trajectory file (any format datasets/trajectory_io.h
  // reads; KITTI needs trajectory_times_file). Stamps of the output start at
  // 0 at the spline's first valid time; the duration is capped at the
  // spline's.
  std::string trajectory_file;
  std::string trajectory_times_file;
  bool trajectory_y_down = false;  // The file's world has y down (KITTI).
  uint64_t seed = 1;
};

// Checks ranges; false with a message naming the setting ("inertial.NAME
// ...").
bool ValidateInertialSimulationConfig(const InertialSimulationConfig& config,
                                      std::string* error);

// Fills *data (overwritten): imu, positions, ground_truth (one per IMU
// sample), gravity; has_initial_state with the true state at t = 0.
// Errors: invalid config, unreadable trajectory file ("PATH:LINE: ...").
bool SimulateInertial(const InertialSimulationConfig& config,
                      InertialData* data, std::string* error);

// The same from a given trajectory (config.trajectory* ignored); the
// duration is capped at trajectory.duration().
bool SimulateInertial(const InertialSimulationConfig& config,
                      const SmoothTrajectory& trajectory, InertialData* data,
                      std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_INERTIAL_SIMULATOR_H_
