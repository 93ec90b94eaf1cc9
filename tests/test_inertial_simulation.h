// Simulated IMU + position fixes (datasets/inertial_simulator.h) with a
// consistent start for the inertial estimator tests: the initial biases are
// drawn from the estimator's bias prior (mean zero) and the initial state
// handed to the estimator is the truth perturbed with the prior sigmas. The
// ground truth holds the true state at every IMU sample.
#ifndef SLAM_TESTS_TEST_INERTIAL_SIMULATION_H_
#define SLAM_TESTS_TEST_INERTIAL_SIMULATION_H_

#include <string>

#include "core/lie.h"
#include "datasets/imu_io.h"
#include "datasets/inertial_simulator.h"
#include "frontends/inertial/inertial_estimator.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam::testing {

inline InertialData SimulateConsistentStart(unsigned seed, double duration,
                                            double fix_rate_hz,
                                            const InertialOptions& options) {
  TestRng rng(seed);
  InertialSimulationConfig config;
  config.duration = duration;
  config.imu_rate = 200.0;
  config.position_rate = fix_rate_hz;
  config.position_sigma = options.position_sigma;
  config.noise = options.noise;
  config.gravity = options.gravity;
  config.seed = seed;
  for (int i = 0; i < 3; ++i) {
    config.initial_gyro_bias[i] = options.prior_gyro_bias_sigma * rng.Normal();
    config.initial_accel_bias[i] =
        options.prior_accel_bias_sigma * rng.Normal();
  }
  InertialData data;
  std::string error;
  EXPECT_TRUE(SimulateInertial(config, &data, &error)) << error;
  NavState& init = data.initial_state;
  init.pose.t += options.prior_position_sigma * rng.Normal3();
  init.pose.q =
      init.pose.q * QuaternionExp<double>(Eigen::Vector3d(
                        options.prior_rotation_sigma * rng.Normal3()));
  init.velocity += options.prior_velocity_sigma * rng.Normal3();
  return data;
}

}  // namespace slam::testing

#endif  // SLAM_TESTS_TEST_INERTIAL_SIMULATION_H_
