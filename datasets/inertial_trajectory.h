// Smooth analytic trajectories for the inertial simulator and the inertial
// tests: pose, velocity, acceleration and body angular rate at any time,
// all in closed form (no numerical differentiation), so that noise-free IMU
// readings are exact.
//
// Frames follow core/imu_preintegration.h: the pose maps body to world,
// velocity and acceleration are world-frame derivatives of the position,
// the angular rate omega is in the BODY frame (R^T dR/dt = [omega]x).
#ifndef SLAM_DATASETS_INERTIAL_TRAJECTORY_H_
#define SLAM_DATASETS_INERTIAL_TRAJECTORY_H_

#include <Eigen/Core>

#include "core/lie.h"

namespace slam {

struct TrajectorySample {
  Pose3 pose;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // world
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // world
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();         // body
};

// A 3D Lissajous curve (a figure eight for the default frequencies) with a
// varying attitude given by yaw-pitch-roll angles, R = Rz(yaw) Ry(pitch)
// Rx(roll):
//   p(t)     = center + amplitude .* sin(frequency .* t + phase)
//   yaw(t)   = yaw_rate t + yaw_amplitude sin(yaw_frequency t)
//   pitch(t) = pitch_amplitude sin(pitch_frequency t)
//   roll(t)  = roll_amplitude sin(roll_frequency t + roll_phase)
// Frequencies in rad/s, amplitudes in metres / radians.
struct LissajousParams {
  Eigen::Vector3d center = Eigen::Vector3d(0.0, 0.0, 2.0);
  Eigen::Vector3d amplitude = Eigen::Vector3d(10.0, 5.0, 1.0);
  Eigen::Vector3d frequency = Eigen::Vector3d(0.25, 0.5, 0.3);
  Eigen::Vector3d phase = Eigen::Vector3d(0.0, 0.0, 0.5);
  double yaw_rate = 0.1;
  double yaw_amplitude = 0.5;
  double yaw_frequency = 0.25;
  double pitch_amplitude = 0.15;
  double pitch_frequency = 0.7;
  double roll_amplitude = 0.2;
  double roll_frequency = 0.9;
  double roll_phase = 0.5;
};

class LissajousTrajectory {
 public:
  explicit LissajousTrajectory(const LissajousParams& params = {})
      : params_(params) {}
  // t in seconds.
  TrajectorySample Evaluate(double t) const;
  const LissajousParams& params() const { return params_; }

 private:
  LissajousParams params_;
};

}  // namespace slam

#endif  // SLAM_DATASETS_INERTIAL_TRAJECTORY_H_
