// A trajectory: time-stamped SE(3) poses (2D poses are lifted with z = 0 and
// a rotation about z). Plain data shared by the estimators, the evaluation
// metrics and the trajectory file readers/writers.
#ifndef SLAM_CORE_TRAJECTORY_H_
#define SLAM_CORE_TRAJECTORY_H_

#include <vector>

#include "core/conventions.h"
#include "core/lie.h"

namespace slam {

struct StampedPose {
  TimeNs stamp = 0;  // Nanoseconds.
  Pose3 pose;        // Body to world.
};

using Trajectory = std::vector<StampedPose>;

inline Pose3 LiftPose2(const Pose2& p) {
  return Pose3(
      Eigen::Vector3d(p.t.x(), p.t.y(), 0.0),
      Eigen::Quaterniond(Eigen::AngleAxisd(p.theta, Eigen::Vector3d::UnitZ())));
}

}  // namespace slam

#endif  // SLAM_CORE_TRAJECTORY_H_
