// Bias random-walk factor between the IMU biases of two keyframes.
//
// The biases follow b_dot = n_b with white n_b of density sigma_g (gyro) and
// sigma_a (accel) (rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz)), so over dt seconds
// b_j - b_i ~ N(0, diag(sigma_g^2 dt I3, sigma_a^2 dt I3)).
// Parameter blocks: bias_i (6: bg, ba), bias_j (6). Residuals: 6.
// Error: e = b_j - b_i, order (bg, ba).
// Residual: r = L^T e with Omega = L L^T (6x6 over (bg, ba)).
#ifndef SLAM_FACTORS_BIAS_RANDOM_WALK_H_
#define SLAM_FACTORS_BIAS_RANDOM_WALK_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"

namespace slam {

class BiasRandomWalkFactor {
 public:
  explicit BiasRandomWalkFactor(
      const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const bias_i, const T* const bias_j,
                  T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 6, 1>> b_i(bias_i);
    Eigen::Map<const Eigen::Matrix<T, 6, 1>> b_j(bias_j);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (b_j - b_i);
    return true;
  }

  static ceres::CostFunction* Create(
      const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<BiasRandomWalkFactor, 6, 6, 6>(
        new BiasRandomWalkFactor(sqrt_information));
  }

 private:
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_BIAS_RANDOM_WALK_H_
