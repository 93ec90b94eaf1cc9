// Ray casting against line-segment walls: synthetic laser scans with known
// poses for the scan-matching and laser-SLAM tests and demos.
#ifndef SLAM_FRONTENDS_LASER_SCAN_SIMULATOR_H_
#define SLAM_FRONTENDS_LASER_SCAN_SIMULATOR_H_

#include <Eigen/Core>
#include <random>
#include <vector>

#include "core/lie.h"

namespace slam {

struct Wall {
  Eigen::Vector2d a, b;
};

// A closed rectangle [x0, x1] x [y0, y1] as four walls.
std::vector<Wall> RectangleWalls(double x0, double y0, double x1, double y1);

struct ScanGeometry {
  double angle_min = -M_PI / 2;
  double angle_increment = M_PI / 180;
  int num_beams = 181;
  double max_range = 30.0;
};

// Ranges seen from the laser pose (world frame). Beams that hit nothing
// within max_range read max_range. Gaussian range noise of `sigma` when
// `rng` is given.
std::vector<float> SimulateScan(const std::vector<Wall>& walls,
                                const Pose2& laser_pose,
                                const ScanGeometry& geometry, double sigma,
                                std::mt19937* rng);

// Odometry faults seen in real logs, applied to a clean odometry sequence
// (one pose per scan):
//  - kFreeze: the odometry repeats pose first-1 for scans first ..
//    first+length-1, then catches up at once (the increments after the
//    freeze are right again): MIT CSAIL's wheel-encoder dropout.
//  - kJump: the increment into scan `first` is composed with `jump` (a wrong
//    increment), all later increments are right, so every later pose is off
//    by it.
//  - kRotationSlip: the rotation of the increments into scans first ..
//    first+length-1 is multiplied by `rotation_scale` (wheels slipping in a
//    turn), the later increments are right.
struct OdometryFault {
  enum Kind { kFreeze, kJump, kRotationSlip };
  Kind kind = kFreeze;
  int first = 1;
  int length = 1;
  Pose2 jump;
  double rotation_scale = 1.0;
};
std::vector<Pose2> ApplyOdometryFault(const std::vector<Pose2>& odometry,
                                      const OdometryFault& fault);

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_SCAN_SIMULATOR_H_
