// Relative-pose factor between two SE(3) poses (odometry, loop closure).
//
// Frames: X_i, X_j map body coordinates to world coordinates; the measurement
// Z_ij = (t, q) is the pose of j expressed in the frame of i.
// Error (exactly g2o's EdgeSE3, so that chi2 matches g2o on the same file):
//   E = Z_ij^-1 (X_i^-1 X_j),  e = (t_E, vec(q_E)) with the sign of q_E chosen
//   so that w >= 0. The rotation part is the quaternion vector, about HALF
//   the rotation angle: g2o files give their information in these units.
// Residual: r = L^T e with Omega = L L^T (6x6 over (t, qvec)).
// Parameter blocks: X_i (7: t, q xyzw), X_j (7). Residuals: 6.
#ifndef SLAM_FACTORS_BETWEEN_SE3_H_
#define SLAM_FACTORS_BETWEEN_SE3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/autodiff_cost_function.h"

namespace slam {

class BetweenSE3Factor {
 public:
  BetweenSE3Factor(const Eigen::Vector3d& t_measured,
                   const Eigen::Quaterniond& q_measured,
                   const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : t_inv_(-(q_measured.normalized().conjugate() * t_measured)),
        q_inv_(q_measured.normalized().conjugate()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const xi, const T* const xj, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(xi);
    Eigen::Map<const Eigen::Quaternion<T>> q_i(xi + 3);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_j(xj);
    Eigen::Map<const Eigen::Quaternion<T>> q_j(xj + 3);
    const Eigen::Quaternion<T> q_i_inv = q_i.conjugate();
    const Eigen::Matrix<T, 3, 1> t_ij = q_i_inv * (t_j - t_i);
    const Eigen::Quaternion<T> q_ij = q_i_inv * q_j;
    const Eigen::Quaternion<T> q_zinv = q_inv_.cast<T>();
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = q_zinv * t_ij + t_inv_.cast<T>();
    Eigen::Quaternion<T> q_e = q_zinv * q_ij;
    if (q_e.w() < T(0)) q_e.coeffs() = -q_e.coeffs();
    e.template tail<3>() = q_e.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(
      const Eigen::Vector3d& t_measured, const Eigen::Quaterniond& q_measured,
      const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<BetweenSE3Factor, 6, 7, 7>(
        new BetweenSE3Factor(t_measured, q_measured, sqrt_information));
  }

 private:
  Eigen::Vector3d t_inv_;     // Translation of Z_ij^-1.
  Eigen::Quaterniond q_inv_;  // Rotation of Z_ij^-1.
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_BETWEEN_SE3_H_
