// Relative position of a 2D point landmark observed from an SE(2) pose
// (g2o's EDGE_SE2_XY / EdgeSE2PointXY, iSAM's LANDMARK in 2D).
//
// Frames: X = (x, y, theta) maps the robot frame to the world frame; the
// landmark l = (lx, ly) is in the world frame; the measurement z = (zx, zy) is
// the landmark in the robot frame.
// Error (exactly g2o's): e = R(theta)^T (l - t) - z.
// Residual: r = L^T e with Omega = L L^T (2x2 over (x, y) in the robot frame).
// Parameter blocks: X (3), l (2). Residuals: 2.
#ifndef SLAM_FACTORS_RELATIVE_POINT2_H_
#define SLAM_FACTORS_RELATIVE_POINT2_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "core/lie.h"

namespace slam {

class RelativePoint2Factor {
 public:
  RelativePoint2Factor(const Eigen::Vector2d& measurement,
                       const Eigen::Matrix2d& sqrt_information)
      : measurement_(measurement), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, const T* const l, T* residual) const {
    const Eigen::Matrix<T, 2, 1> e =
        RotationMatrix2D(x[2]).transpose() *
            Eigen::Matrix<T, 2, 1>(l[0] - x[0], l[1] - x[1]) -
        measurement_.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& measurement,
                                     const Eigen::Matrix2d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoint2Factor, 2, 3, 2>(
        new RelativePoint2Factor(measurement, sqrt_information));
  }

 private:
  Eigen::Vector2d measurement_;
  Eigen::Matrix2d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_RELATIVE_POINT2_H_
