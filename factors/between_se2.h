// Relative-pose factor between two SE(2) poses (odometry, loop closure).
//
// Frames: X_i, X_j map body coordinates to world coordinates; the measurement
// Z_ij = (x, y, theta) is the pose of j expressed in the frame of i.
// Error (exactly g2o's EdgeSE2):
//   e = t2v(Z_ij^-1 (X_i^-1 X_j)),  e = (ex, ey, etheta), etheta wrapped.
// Residual: r = L^T e with Omega = L L^T (Omega over (x, y, theta)), so that
// |r|^2 = e^T Omega e is g2o's chi2 of the edge.
// Parameter blocks: X_i (3), X_j (3). Residuals: 3.
#ifndef SLAM_FACTORS_BETWEEN_SE2_H_
#define SLAM_FACTORS_BETWEEN_SE2_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "core/lie.h"

namespace slam {

class BetweenSE2Factor {
 public:
  BetweenSE2Factor(const Eigen::Vector3d& measurement,
                   const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const xi, const T* const xj, T* residual) const {
    const Eigen::Matrix<T, 2, 1> d(xj[0] - xi[0], xj[1] - xi[1]);
    const Eigen::Matrix<T, 2, 1> t_ij = RotationMatrix2D(xi[2]).transpose() * d;
    const Eigen::Matrix<T, 2, 1> t_z = measurement_.head<2>().cast<T>();
    Eigen::Matrix<T, 3, 1> e;
    e.template head<2>() =
        RotationMatrix2D(T(measurement_[2])).transpose() * (t_ij - t_z);
    e[2] = NormalizeAngle(xj[2] - xi[2] - T(measurement_[2]));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& measurement,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<BetweenSE2Factor, 3, 3, 3>(
        new BetweenSE2Factor(measurement, sqrt_information));
  }

 private:
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_BETWEEN_SE2_H_
