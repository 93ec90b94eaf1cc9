// Relative motion between two odometry poses and its covariance under the
// differential-drive odometry motion model (Thrun, Burgard, Fox,
// "Probabilistic Robotics", 2005, sec. 5.4, sample_motion_model_odometry).
//
// The motion from odometry pose A to B is decomposed into a first rotation,
// a translation and a second rotation:
//   rot1 = atan2(dy, dx) - theta_A,  trans = |(dx, dy)|,
//   rot2 = theta_B - theta_A - rot1,
// (for backward motion, |rot1| > pi/2, the translation is taken negative
// and rot1 flipped by pi, so that a small reverse step is a small rot1), each
// with an independent zero-mean error of variance
//   var(rot1)  = alpha1 rot1^2 + alpha2 trans^2
//   var(trans) = alpha3 trans^2 + alpha4 (rot1^2 + rot2^2)
//   var(rot2)  = alpha1 rot2^2 + alpha2 trans^2.
// (The book writes the model with standard deviations alpha1 |rot1| +
// alpha2 |trans|; we use the variance form of its table 5.6.) The relative
// pose in A's frame, (trans cos rot1, trans sin rot1, rot1 + rot2), has the
// first-order covariance J diag(var) J^T, J its Jacobian over (rot1, trans,
// rot2), plus a floor diag(min_sigma_xy^2, min_sigma_xy^2,
// min_sigma_theta^2) that keeps it positive definite when the robot stands
// still. The covariance is over the (dx, dy, dtheta) error of a between
// factor in A's frame, the right-perturbation convention of the graph.
#ifndef SLAM_FRONTENDS_LASER_ODOMETRY_MODEL_H_
#define SLAM_FRONTENDS_LASER_ODOMETRY_MODEL_H_

#include <Eigen/Core>

#include "core/lie.h"

namespace slam {

struct OdometryNoise {
  double alpha1 = 0.05;            // rad^2/rad^2: rotation from rotation.
  double alpha2 = 0.01;            // rad^2/m^2: rotation from translation.
  double alpha3 = 0.05;            // m^2/m^2: translation from translation.
  double alpha4 = 0.01;            // m^2/rad^2: translation from rotation.
  double min_sigma_xy = 0.005;     // m.
  double min_sigma_theta = 0.002;  // rad.
};

struct OdometryDelta {
  Pose2 delta;  // B in the frame of A.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

OdometryDelta OdometryMotion(const Pose2& a, const Pose2& b,
                             const OdometryNoise& noise);

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_ODOMETRY_MODEL_H_
