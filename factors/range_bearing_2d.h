// Range-bearing observation of a 2D point landmark from an SE(2) pose.
//
// Frames: X = (x, y, theta) maps the robot frame to the world frame; the
// landmark l = (lx, ly) is in the world frame. With d = R(theta)^T (l - t)
// the landmark in the robot frame, the prediction is
//   range = |d|,  bearing = atan2(d.y, d.x)  (radians, counter-clockwise
//   from the robot's x axis).
// Error (residual order range, bearing):
//   e = (range_pred - range_meas, wrap(bearing_pred - bearing_meas)).
// Residual: r = L^T e with Omega = L L^T (2x2 over (range, bearing)).
// Parameter blocks: X (3), l (2). Residuals: 2.
// The landmark must not sit on the robot (range 0): the bearing and its
// derivative are undefined there; the factor then returns false.
#ifndef SLAM_FACTORS_RANGE_BEARING_2D_H_
#define SLAM_FACTORS_RANGE_BEARING_2D_H_

#include <Eigen/Core>
#include <cmath>

#include "ceres/autodiff_cost_function.h"
#include "core/lie.h"

namespace slam {

class RangeBearing2Factor {
 public:
  RangeBearing2Factor(double range, double bearing,
                      const Eigen::Matrix2d& sqrt_information)
      : range_(range), bearing_(bearing), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, const T* const l, T* residual) const {
    using std::atan2;
    using std::sqrt;
    const Eigen::Matrix<T, 2, 1> d =
        RotationMatrix2D(x[2]).transpose() *
        Eigen::Matrix<T, 2, 1>(l[0] - x[0], l[1] - x[1]);
    const T range_sq = d.squaredNorm();
    if (!(range_sq > T(1e-18))) return false;
    Eigen::Matrix<T, 2, 1> e;
    e[0] = sqrt(range_sq) - T(range_);
    e[1] = NormalizeAngle(atan2(d.y(), d.x()) - T(bearing_));
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(double range, double bearing,
                                     const Eigen::Matrix2d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RangeBearing2Factor, 2, 3, 2>(
        new RangeBearing2Factor(range, bearing, sqrt_information));
  }

 private:
  double range_;
  double bearing_;
  Eigen::Matrix2d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_RANGE_BEARING_2D_H_
