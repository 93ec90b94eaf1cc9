// Prior on a Euclidean node of N values (velocity: N = 3, IMU bias: N = 6).
//
// Measurement z in node storage form (velocity in the world frame; bias
// (bg, ba) in the body frame).
// Error: e = x - z, in the node's storage order.
// Residual: r = L^T e with Omega = L L^T (N x N).
// Parameter blocks: x (N). Residuals: N.
#ifndef SLAM_FACTORS_EUCLIDEAN_PRIOR_H_
#define SLAM_FACTORS_EUCLIDEAN_PRIOR_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"

namespace slam {

template <int N>
class EuclideanPriorFactor {
 public:
  using VectorN = Eigen::Matrix<double, N, 1>;
  using MatrixN = Eigen::Matrix<double, N, N>;

  EuclideanPriorFactor(const VectorN& measured, const MatrixN& sqrt_information)
      : z_(measured), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, N, 1>> v(x);
    Eigen::Map<Eigen::Matrix<T, N, 1>> r(residual);
    r = sqrt_information_.template cast<T>() * (v - z_.template cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const VectorN& measured,
                                     const MatrixN& sqrt_information) {
    return new ceres::AutoDiffCostFunction<EuclideanPriorFactor, N, N>(
        new EuclideanPriorFactor(measured, sqrt_information));
  }

 private:
  VectorN z_;
  MatrixN sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_EUCLIDEAN_PRIOR_H_
