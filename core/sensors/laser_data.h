// The raw data of the 2D laser frontend (frontends/laser/): laser scans and
// wheel odometry readings. Neutral types: the CARMEN reader
// (datasets/carmen_io.h, which documents how each field is read from a log)
// and the scan simulator fill them, the laser pipeline and the occupancy grid
// consume them, without either side depending on the other.
//
// Frames: the robot frame (x forward, y left) and the laser frame; angles in
// radians, distances in metres, stamps in nanoseconds (core/conventions.h).
#ifndef SLAM_CORE_SENSORS_LASER_DATA_H_
#define SLAM_CORE_SENSORS_LASER_DATA_H_

#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"

namespace slam {

// One scan: beam i has the angle angle_min + i * angle_increment in the
// laser frame; readings at or beyond max_range mean "no return".
struct LaserScan {
  TimeNs stamp = 0;    // ipc_timestamp.
  Pose2 odom;          // Robot odometry pose at the scan.
  Pose2 laser_offset;  // Robot -> laser.
  Pose2 logged_pose;   // The other pose of the line (see carmen_io.h).
  double angle_min = 0.0;
  double angle_increment = 0.0;
  double max_range = 0.0;
  std::vector<float> ranges;
  std::string tag;  // "FLASER", "RLASER" or "ROBOTLASER1".
  int line = 0;     // 1-based line in the (decompressed) log.
};

struct OdometryReading {
  TimeNs stamp = 0;  // ipc_timestamp.
  Pose2 pose;
  double tv = 0.0;  // Translational velocity (m/s).
  double rv = 0.0;  // Rotational velocity (rad/s).
};

}  // namespace slam

#endif  // SLAM_CORE_SENSORS_LASER_DATA_H_
