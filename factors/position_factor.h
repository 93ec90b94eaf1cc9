// Position (GPS-like) factor on one SE(3) pose, with an optional lever arm.
//
// Frames: X = (t, R) maps body to world; the antenna sits at lever_arm in the
// body frame, so its world position is t + R lever_arm. The measurement z is
// that position in the world frame.
// Error: e = t + R lever_arm - z (world frame, metres).
// Residual: r = L^T e with Omega = L L^T (3x3).
// Parameter blocks: X (7: t, q xyzw). Residuals: 3.
#ifndef SLAM_FACTORS_POSITION_FACTOR_H_
#define SLAM_FACTORS_POSITION_FACTOR_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/autodiff_cost_function.h"

namespace slam {

class PositionFactor {
 public:
  PositionFactor(const Eigen::Vector3d& position_measured,
                 const Eigen::Vector3d& lever_arm,
                 const Eigen::Matrix3d& sqrt_information)
      : z_(position_measured),
        lever_arm_(lever_arm),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x);
    Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Matrix<T, 3, 1> e =
        t + q * lever_arm_.cast<T>() - z_.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& position_measured,
                                     const Eigen::Vector3d& lever_arm,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<PositionFactor, 3, 7>(
        new PositionFactor(position_measured, lever_arm, sqrt_information));
  }

 private:
  Eigen::Vector3d z_;
  Eigen::Vector3d lever_arm_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_POSITION_FACTOR_H_
