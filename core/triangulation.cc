#include "core/triangulation.h"

#include <cmath>

namespace slam {

Eigen::Vector2d InvertRangeBearing(const Pose2& pose, double range,
                                   double bearing) {
  const double angle = pose.theta + bearing;
  return pose.t + range * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

bool TriangulateStereo(const Pose3& camera, double fx, double fy, double cx,
                       double cy, double baseline,
                       const Eigen::Vector3d& uL_uR_v, Eigen::Vector3d* point) {
  const double disparity = uL_uR_v[0] - uL_uR_v[1];
  if (!(disparity > 0.0) || !(fx > 0.0) || !(fy > 0.0)) return false;
  const double z = fx * baseline / disparity;
  const Eigen::Vector3d p_camera((uL_uR_v[0] - cx) * z / fx,
                                 (uL_uR_v[2] - cy) * z / fy, z);
  *point = camera * p_camera;
  return point->allFinite();
}

bool TriangulateMidpoint(const Eigen::Vector3d& o1, const Eigen::Vector3d& d1,
                         const Eigen::Vector3d& o2, const Eigen::Vector3d& d2,
                         Eigen::Vector3d* point, double min_sin_angle) {
  const double n1 = d1.norm();
  const double n2 = d2.norm();
  if (!(n1 > 0.0) || !(n2 > 0.0)) return false;
  const Eigen::Vector3d u = d1 / n1;
  const Eigen::Vector3d v = d2 / n2;
  // Minimize |o1 + s u - o2 - t v|^2: [1 -b; b -1] [s; t] = [-u.w; -v.w]
  // with w = o1 - o2, b = u.v.
  const double b = u.dot(v);
  const double denom = 1.0 - b * b;  // sin^2 of the angle between the rays.
  if (!(denom > min_sin_angle * min_sin_angle)) return false;
  const Eigen::Vector3d w = o1 - o2;
  const double d = u.dot(w);
  const double e = v.dot(w);
  const double s = (b * e - d) / denom;
  const double t = (e - b * d) / denom;
  if (!(s > 0.0) || !(t > 0.0)) return false;
  *point = 0.5 * ((o1 + s * u) + (o2 + t * v));
  return point->allFinite();
}

}  // namespace slam
