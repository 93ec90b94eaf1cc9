// The raw data of the inertial estimators (frontends/inertial/): IMU
// readings, position fixes and ground truth (pose, velocity, biases). Neutral
// types: the readers (datasets/imu_io.h, which documents how each format
// fills them) and the inertial simulator fill them, the estimators consume
// them, without either side depending on the other.
//
// Stamps are int64 nanoseconds and quaternions follow core/conventions.h
// (x, y, z, w); the IMU readings themselves are core/imu_preintegration.h's
// ImuSample.
#ifndef SLAM_CORE_SENSORS_INERTIAL_DATA_H_
#define SLAM_CORE_SENSORS_INERTIAL_DATA_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/conventions.h"
#include "core/imu_preintegration.h"
#include "core/lie.h"

namespace slam {

struct PositionFix {
  TimeNs stamp = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world frame
  // GTSAM CSV only: the ground-truth rotation written on the GPS row.
  bool has_orientation = false;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct InertialGroundTruth {
  TimeNs stamp = 0;
  Pose3 pose;                                          // body to world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // world
  ImuBias bias = ImuBias::Zero();                      // (bg, ba)
};

struct InertialData {
  std::vector<ImuSample> imu;
  std::vector<PositionFix> positions;
  std::vector<InertialGroundTruth> ground_truth;  // May be empty.
  // How to integrate `imu` (IntegrateImuSamples): kHold for the GTSAM CSV
  // (rows held over dt), kLinear for EuRoC folders and the simulator.
  ImuInterpolation interpolation = ImuInterpolation::kLinear;
  // GTSAM CSV: the "i" row (velocity included).
  bool has_initial_state = false;
  NavState initial_state;
  Eigen::Vector3d gravity = DefaultGravity();
  // Where the IMU readings came from (EuRoC reader): the file and the line
  // of each reading, for messages about them. Empty otherwise.
  std::string imu_path;
  std::vector<int64_t> imu_lines;
};

}  // namespace slam

#endif  // SLAM_CORE_SENSORS_INERTIAL_DATA_H_
