// Smooth trajectories for the inertial simulator and the inertial tests
// (a built-in Lissajous curve, or a spline through a recorded trajectory):
// pose, velocity, acceleration and body angular rate at any time, all in closed
// form (no numerical differentiation), so that noise-free IMU readings are
// exact.
//
// Frames follow core/imu_preintegration.h: the pose maps body to world,
// velocity and acceleration are world-frame derivatives of the position,
// the angular rate omega is in the BODY frame (R^T dR/dt = [omega]x).
#ifndef SLAM_DATASETS_INERTIAL_TRAJECTORY_H_
#define SLAM_DATASETS_INERTIAL_TRAJECTORY_H_

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "core/lie.h"
#include "core/trajectory.h"

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

// A trajectory defined for t in [0, duration()] seconds.
class SmoothTrajectory {
 public:
  virtual ~SmoothTrajectory() = default;
  virtual TrajectorySample Evaluate(double t) const = 0;
  virtual double duration() const = 0;
};

class LissajousTrajectory : public SmoothTrajectory {
 public:
  explicit LissajousTrajectory(const LissajousParams& params = {})
      : params_(params) {}
  // t in seconds.
  TrajectorySample Evaluate(double t) const override;
  // Unbounded: the curve is defined for every t.
  double duration() const override {
    return std::numeric_limits<double>::infinity();
  }
  const LissajousParams& params() const { return params_; }

 private:
  LissajousParams params_;
};

// A uniform cubic B-spline through a recorded trajectory (e.g. KITTI ground
// truth), C2 in position and in rotation:
//   Control poses: the recorded poses resampled at n uniform knot times
//   t_k = t_first + k h, h = (t_last - t_first) / (n - 1) (position linearly
//   interpolated, rotation by slerp), so stamps need not be uniform.
//   Position: the cumulative cubic B-spline p(u) = c_i + sum_{j=1..3}
//   B_j(u) (c_{i+j} - c_{i+j-1}) on segment i, u in [0, 1).
//   Rotation: the cumulative B-spline on SO(3) (Kim et al. 1995; Sommer et
//   al. 2020), R(u) = R_i prod_{j=1..3} Exp(B_j(u) Omega_j), Omega_j =
//   Log(R_{i+j-1}^T R_{i+j}); body rate by the recursion
//   w_j = A_j^T w_{j-1} + B_j'(u) / h Omega_j, A_j = Exp(B_j(u) Omega_j).
//   Velocity and acceleration: the analytic derivatives of p.
// The spline approximates (smooths) the poses: it does not pass through
// them exactly. It is valid on [t_1, t_{n-2}]; Evaluate(t) takes
// t in [0, duration()] from t_1 on (clamped outside).
class SplineTrajectory : public SmoothTrajectory {
 public:
  // poses: at least 4, stamps strictly increasing. y_down_world: the
  // poses' world frame has y pointing down and z forward (KITTI's camera
  // frame): the world is rotated to x forward, y left, z up, so that
  // gravity is (0, 0, -g). False with *error otherwise.
  bool Fit(const std::vector<StampedPose>& poses, bool y_down_world,
           std::string* error);
  TrajectorySample Evaluate(double t) const override;
  double duration() const override { return duration_; }
  // The stamp (ns) of t = 0 in the recorded time.
  TimeNs start_stamp() const { return start_stamp_; }

 private:
  std::vector<Eigen::Vector3d> positions_;
  std::vector<Eigen::Quaterniond> rotations_;
  std::vector<Eigen::Vector3d> omegas_;  // Log(R_{k-1}^T R_k), omegas_[0] = 0.
  double knot_spacing_ = 1.0;
  double duration_ = 0.0;
  TimeNs start_stamp_ = 0;
};

}  // namespace slam

#endif  // SLAM_DATASETS_INERTIAL_TRAJECTORY_H_
