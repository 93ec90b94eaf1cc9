#include "datasets/inertial_trajectory.h"

#include <Eigen/Geometry>
#include <cmath>

namespace slam {

TrajectorySample LissajousTrajectory::Evaluate(double t) const {
  const LissajousParams& p = params_;
  TrajectorySample s;
  Eigen::Vector3d position;
  for (int k = 0; k < 3; ++k) {
    const double w = p.frequency[k];
    const double arg = w * t + p.phase[k];
    position[k] = p.center[k] + p.amplitude[k] * std::sin(arg);
    s.velocity[k] = p.amplitude[k] * w * std::cos(arg);
    s.acceleration[k] = -p.amplitude[k] * w * w * std::sin(arg);
  }
  const double yaw =
      p.yaw_rate * t + p.yaw_amplitude * std::sin(p.yaw_frequency * t);
  const double yaw_dot = p.yaw_rate + p.yaw_amplitude * p.yaw_frequency *
                                          std::cos(p.yaw_frequency * t);
  const double pitch = p.pitch_amplitude * std::sin(p.pitch_frequency * t);
  const double pitch_dot =
      p.pitch_amplitude * p.pitch_frequency * std::cos(p.pitch_frequency * t);
  const double roll_arg = p.roll_frequency * t + p.roll_phase;
  const double roll = p.roll_amplitude * std::sin(roll_arg);
  const double roll_dot =
      p.roll_amplitude * p.roll_frequency * std::cos(roll_arg);

  const Eigen::Matrix3d rz =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d ry =
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d rx =
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // R^T dR/dt = [(Ry Rx)^T yaw_dot e_z + Rx^T pitch_dot e_y + roll_dot e_x]x.
  s.omega = (ry * rx).transpose() * Eigen::Vector3d(0, 0, yaw_dot) +
            rx.transpose() * Eigen::Vector3d(0, pitch_dot, 0) +
            Eigen::Vector3d(roll_dot, 0, 0);
  s.pose = Pose3(position, Eigen::Quaterniond(rz * ry * rx));
  return s;
}

}  // namespace slam
