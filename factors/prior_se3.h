// Absolute prior on one SE(3) pose.
//
// Frames: X maps body to world; the measurement Z = (t, q) is the expected
// pose in the world frame.
// Error (g2o's EdgeSE3Prior with identity offset): E = Z^-1 X,
//   e = (t_E, vec(q_E)), sign of q_E chosen so that w >= 0 (half-angle units).
// Residual: r = L^T e with Omega = L L^T (6x6 over (t, qvec)).
// Parameter blocks: X (7). Residuals: 6.
#ifndef SLAM_FACTORS_PRIOR_SE3_H_
#define SLAM_FACTORS_PRIOR_SE3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/autodiff_cost_function.h"

namespace slam {

class PriorSE3Factor {
 public:
  PriorSE3Factor(const Eigen::Vector3d& t_measured,
                 const Eigen::Quaterniond& q_measured,
                 const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : t_(t_measured),
        q_inv_(q_measured.conjugate().normalized()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x);
    Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Quaternion<T> q_zinv = q_inv_.cast<T>();
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = q_zinv * (t - t_.cast<T>());
    Eigen::Quaternion<T> q_e = q_zinv * q;
    if (q_e.w() < T(0)) q_e.coeffs() = -q_e.coeffs();
    e.template tail<3>() = q_e.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(
      const Eigen::Vector3d& t_measured, const Eigen::Quaterniond& q_measured,
      const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<PriorSE3Factor, 6, 7>(
        new PriorSE3Factor(t_measured, q_measured, sqrt_information));
  }

 private:
  Eigen::Vector3d t_;
  Eigen::Quaterniond q_inv_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_PRIOR_SE3_H_
