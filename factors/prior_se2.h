// Absolute prior on one SE(2) pose.
//
// Frames: X maps body to world; the measurement Z = (x, y, theta) is the
// expected pose in the world frame.
// Error (g2o's EdgeSE2Prior): e = t2v(Z^-1 X) = (R_z^T (t - t_z),
//   wrap(theta - theta_z)).
// Residual: r = L^T e with Omega = L L^T over (x, y, theta).
// Parameter blocks: X (3). Residuals: 3.
#ifndef SLAM_FACTORS_PRIOR_SE2_H_
#define SLAM_FACTORS_PRIOR_SE2_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "core/lie.h"

namespace slam {

class PriorSE2Factor {
 public:
  PriorSE2Factor(const Eigen::Vector3d& measurement,
                 const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    const Eigen::Matrix<T, 2, 1> d(x[0] - T(measurement_[0]),
                                   x[1] - T(measurement_[1]));
    Eigen::Matrix<T, 3, 1> e;
    e.template head<2>() = RotationMatrix2D(T(measurement_[2])).transpose() * d;
    e[2] = NormalizeAngle(x[2] - T(measurement_[2]));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& measurement,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<PriorSE2Factor, 3, 3>(
        new PriorSE2Factor(measurement, sqrt_information));
  }

 private:
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_PRIOR_SE2_H_
