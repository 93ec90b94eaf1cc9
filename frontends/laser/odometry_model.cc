#include "frontends/laser/odometry_model.h"

#include <cmath>

namespace slam {

OdometryDelta OdometryMotion(const Pose2& a, const Pose2& b,
                             const OdometryNoise& noise) {
  OdometryDelta out;
  out.delta = a.Inverse() * b;
  const Eigen::Vector2d d = out.delta.t;  // In A's frame.
  double trans = d.norm();
  double rot1 = trans > 1e-9 ? std::atan2(d.y(), d.x()) : 0.0;
  if (std::abs(rot1) > M_PI / 2) {  // Driving backwards.
    rot1 = NormalizeAngle(rot1 + M_PI);
    trans = -trans;
  }
  const double rot2 = NormalizeAngle(out.delta.theta - rot1);
  const Eigen::Vector3d var(
      noise.alpha1 * rot1 * rot1 + noise.alpha2 * trans * trans,
      noise.alpha3 * trans * trans + noise.alpha4 * (rot1 * rot1 + rot2 * rot2),
      noise.alpha1 * rot2 * rot2 + noise.alpha2 * trans * trans);
  const double c = std::cos(rot1), s = std::sin(rot1);
  Eigen::Matrix3d j;
  j << -trans * s, c, 0.0,  //
      trans * c, s, 0.0,    //
      1.0, 0.0, 1.0;
  out.covariance = j * var.asDiagonal() * j.transpose();
  out.covariance.diagonal() +=
      Eigen::Vector3d(noise.min_sigma_xy * noise.min_sigma_xy,
                      noise.min_sigma_xy * noise.min_sigma_xy,
                      noise.min_sigma_theta * noise.min_sigma_theta);
  return out;
}

}  // namespace slam
