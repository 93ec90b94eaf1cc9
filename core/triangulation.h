// Landmark position from one or two observations, in the world frame. The
// functions take plain numbers (no sensor model types): core knows no
// sensor. Camera poses are T_world_camera (camera-to-world), camera frame x
// right, y down, z forward (factors/camera_models.h).
#ifndef SLAM_CORE_TRIANGULATION_H_
#define SLAM_CORE_TRIANGULATION_H_

#include <Eigen/Core>

#include "core/lie.h"

namespace slam {

// The 2D point at `range` along `bearing` (radians, counter-clockwise from
// the robot's x axis) from the SE(2) pose.
Eigen::Vector2d InvertRangeBearing(const Pose2& pose, double range,
                                   double bearing);

// Rectified stereo (uL, uR, v) seen from the left camera `camera`
// (camera-to-world) with focal lengths fx, fy, principal point cx, cy and
// baseline b (right camera at +b along x): depth z = fx b / (uL - uR),
// x = (uL - cx) z / fx, y = (v - cy) z / fy. False (and *point untouched)
// when the disparity uL - uR is not positive (point at infinity or behind).
bool TriangulateStereo(const Pose3& camera, double fx, double fy, double cx,
                       double cy, double baseline,
                       const Eigen::Vector3d& uL_uR_v, Eigen::Vector3d* point);

// Midpoint of the shortest segment between the rays o1 + s d1 and o2 + t d2
// (directions need not be unit length). False when the rays are (nearly)
// parallel (sine of their angle below min_sin_angle) or the closest points
// lie behind either origin (s <= 0 or t <= 0).
bool TriangulateMidpoint(const Eigen::Vector3d& o1, const Eigen::Vector3d& d1,
                         const Eigen::Vector3d& o2, const Eigen::Vector3d& d2,
                         Eigen::Vector3d* point, double min_sin_angle = 1e-6);

}  // namespace slam

#endif  // SLAM_CORE_TRIANGULATION_H_
