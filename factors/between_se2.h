// Relative-pose factor between two SE(2) poses (odometry, loop closure).
//
// Frames: X_i, X_j map body coordinates to world coordinates; the measurement
// Z_ij = (x, y, theta) is the pose of j expressed in the frame of i.
// Error (exactly g2o's EdgeSE2):
//   e = t2v(Z_ij^-1 (X_i^-1 X_j)),  e = (ex, ey, etheta), etheta wrapped.
// Residual: r = L^T e with Omega = L L^T (Omega over (x, y, theta)), so that
// |r|^2 = e^T Omega e is g2o's chi2 of the edge.
// Parameter blocks: X_i (3), X_j (3). Residuals: 3.
//
// Create() returns BetweenSE2CostFunction: the same residual with analytic
// Jacobians over the stored (x, y, theta), with d = t_j - t_i:
//   de_xy/dt_i = -R_z^T R_i^T,  de_xy/dt_j = R_z^T R_i^T,
//   de_xy/dtheta_i = R_z^T (dR_i^T/dtheta) d,  de_theta/dtheta_i = -1,
//   de_theta/dtheta_j = 1.
// The functor's autodiff (CreateAutoDiff) is the reference in tests.
#ifndef SLAM_FACTORS_BETWEEN_SE2_H_
#define SLAM_FACTORS_BETWEEN_SE2_H_

#include <cmath>

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "ceres/sized_cost_function.h"
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

  // The analytic cost function (below).
  static ceres::CostFunction* Create(const Eigen::Vector3d& measurement,
                                     const Eigen::Matrix3d& sqrt_information);

  // Automatic differentiation of operator(): the reference for tests.
  static ceres::CostFunction* CreateAutoDiff(
      const Eigen::Vector3d& measurement,
      const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<BetweenSE2Factor, 3, 3, 3>(
        new BetweenSE2Factor(measurement, sqrt_information));
  }

 private:
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;
};

class BetweenSE2CostFunction final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  BetweenSE2CostFunction(const Eigen::Vector3d& measurement,
                         const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement),
        r_z_inv_(RotationMatrix2D(measurement[2]).transpose()),
        sqrt_information_(sqrt_information) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* xi = parameters[0];
    const double* xj = parameters[1];
    const Eigen::Vector2d d(xj[0] - xi[0], xj[1] - xi[1]);
    const double c = std::cos(xi[2]);
    const double s = std::sin(xi[2]);
    Eigen::Matrix2d r_i_inv;
    r_i_inv << c, s, -s, c;
    Eigen::Vector3d e;
    e.head<2>() = r_z_inv_ * (r_i_inv * d - measurement_.head<2>());
    e[2] = NormalizeAngle(xj[2] - xi[2] - measurement_[2]);
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = sqrt_information_ * e;
    if (jacobians == nullptr) return true;
    const Eigen::Matrix2d a = r_z_inv_ * r_i_inv;
    if (jacobians[0] != nullptr) {
      Eigen::Matrix3d j;
      Eigen::Matrix2d dr_i_inv;
      dr_i_inv << -s, c, -c, -s;
      j.topLeftCorner<2, 2>() = -a;
      j.topRightCorner<2, 1>() = r_z_inv_ * (dr_i_inv * d);
      j.bottomRows<1>() << 0.0, 0.0, -1.0;
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(
          jacobians[0]);
      out = sqrt_information_ * j;
    }
    if (jacobians[1] != nullptr) {
      Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
      j.topLeftCorner<2, 2>() = a;
      j(2, 2) = 1.0;
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(
          jacobians[1]);
      out = sqrt_information_ * j;
    }
    return true;
  }

 private:
  Eigen::Vector3d measurement_;
  Eigen::Matrix2d r_z_inv_;  // R_z^T.
  Eigen::Matrix3d sqrt_information_;
};

inline ceres::CostFunction* BetweenSE2Factor::Create(
    const Eigen::Vector3d& measurement,
    const Eigen::Matrix3d& sqrt_information) {
  return new BetweenSE2CostFunction(measurement, sqrt_information);
}

}  // namespace slam

#endif  // SLAM_FACTORS_BETWEEN_SE2_H_
