// Relative position of a 3D point landmark observed by a sensor mounted on an
// SE(3) pose (g2o's EDGE_SE3_TRACKXYZ / EdgeSE3PointXYZ with its
// PARAMS_SE3OFFSET).
//
// Frames: X = (t, q) maps the body frame to the world frame; the sensor offset
// S = (t_s, q_s) maps the sensor frame to the body frame (identity: the
// sensor is the body); the landmark l is in the world frame; the measurement
// z is the landmark in the sensor frame.
// Error (exactly g2o's): e = (X S)^-1 l - z = R_s^T (R^T (l - t) - t_s) - z.
// Residual: r = L^T e with Omega = L L^T (3x3 over the sensor-frame xyz).
// Parameter blocks: X (7: t, q xyzw), l (3). Residuals: 3.
#ifndef SLAM_FACTORS_RELATIVE_POINT3_H_
#define SLAM_FACTORS_RELATIVE_POINT3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/autodiff_cost_function.h"
#include "core/lie.h"

namespace slam {

class RelativePoint3Factor {
 public:
  RelativePoint3Factor(const Eigen::Vector3d& measurement, const Pose3& offset,
                       const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement),
        offset_t_(offset.t),
        offset_q_inv_(offset.q.conjugate()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, const T* const l, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x);
    Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(l);
    const Eigen::Matrix<T, 3, 1> p_body = q.conjugate() * (p - t);
    const Eigen::Matrix<T, 3, 1> e =
        offset_q_inv_.cast<T>() * (p_body - offset_t_.cast<T>()) -
        measurement_.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& measurement,
                                     const Pose3& offset,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoint3Factor, 3, 7, 3>(
        new RelativePoint3Factor(measurement, offset, sqrt_information));
  }

 private:
  Eigen::Vector3d measurement_;
  Eigen::Vector3d offset_t_;
  Eigen::Quaterniond offset_q_inv_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_RELATIVE_POINT3_H_
