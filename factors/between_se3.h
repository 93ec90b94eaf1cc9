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
//
// Create() returns BetweenSE3CostFunction: the same residual with analytic
// Jacobians (pose graphs spend most of their evaluation time here; autodiff
// took 1.2 us per factor and Jacobian, about 15 % of parking-garage's wall
// time). With the right perturbations of the SE(3) manifold
// (core/conventions.h: t <- t + R rho, R <- R Exp(phi)), A = X_i^-1 X_j =
// (t_A, R_A), R_z the measured rotation, M = 1/2 (w I + [v]x) for q_E =
// (v, w) after its sign choice (d vec(q_E Exp(phi)) / dphi at 0):
//   de/d(rho_i, phi_i) = [ -R_z^T   R_z^T [t_A]x ]
//                        [    0      -M R_A^T    ]
//   de/d(rho_j, phi_j) = [ R_z^T R_A     0 ]
//                        [    0          M ]
// Ceres asks for Jacobians over the 7 stored values; they are returned as
// J_tangent P^+, P^+ = [R^T 0; 0 4 Q^T] the left inverse of the manifold's
// PlusJacobian P = [R 0; 0 Q], so that Ceres' J_ambient P is exactly the
// tangent Jacobian (the component along the quaternion's norm, which the
// manifold never moves, is left out). The functor's autodiff is the
// reference in tests (factors_test.cc) besides numeric differentiation.
#ifndef SLAM_FACTORS_BETWEEN_SE3_H_
#define SLAM_FACTORS_BETWEEN_SE3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/autodiff_cost_function.h"
#include "ceres/sized_cost_function.h"
#include "core/lie.h"

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

  // The analytic cost function (below).
  static ceres::CostFunction* Create(
      const Eigen::Vector3d& t_measured, const Eigen::Quaterniond& q_measured,
      const Eigen::Matrix<double, 6, 6>& sqrt_information);

  // Automatic differentiation of operator(): the reference for tests.
  static ceres::CostFunction* CreateAutoDiff(
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

class BetweenSE3CostFunction final : public ceres::SizedCostFunction<6, 7, 7> {
 public:
  BetweenSE3CostFunction(const Eigen::Vector3d& t_measured,
                         const Eigen::Quaterniond& q_measured,
                         const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : t_inv_(-(q_measured.normalized().conjugate() * t_measured)),
        q_inv_(q_measured.normalized().conjugate()),
        r_inv_(q_inv_.toRotationMatrix()),
        sqrt_information_(sqrt_information) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<const Eigen::Vector3d> t_i(parameters[0]);
    Eigen::Map<const Eigen::Quaterniond> q_i(parameters[0] + 3);
    Eigen::Map<const Eigen::Vector3d> t_j(parameters[1]);
    Eigen::Map<const Eigen::Quaterniond> q_j(parameters[1] + 3);
    const Eigen::Quaterniond q_i_inv = q_i.conjugate();
    const Eigen::Vector3d t_a = q_i_inv * (t_j - t_i);
    const Eigen::Quaterniond q_a = q_i_inv * q_j;
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = r_inv_ * t_a + t_inv_;
    Eigen::Quaterniond q_e = q_inv_ * q_a;
    if (q_e.w() < 0.0) q_e.coeffs() = -q_e.coeffs();
    e.tail<3>() = q_e.vec();
    Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
    r = sqrt_information_ * e;
    if (jacobians == nullptr) return true;
    const Eigen::Matrix3d r_a = q_a.toRotationMatrix();
    const Eigen::Matrix3d m =
        0.5 * (q_e.w() * Eigen::Matrix3d::Identity() + Skew<double>(q_e.vec()));
    Eigen::Matrix<double, 6, 6> tangent;
    if (jacobians[0] != nullptr) {
      tangent.topLeftCorner<3, 3>() = -r_inv_;
      tangent.topRightCorner<3, 3>() = r_inv_ * Skew<double>(t_a);
      tangent.bottomLeftCorner<3, 3>().setZero();
      tangent.bottomRightCorner<3, 3>() = -m * r_a.transpose();
      ToAmbient(sqrt_information_ * tangent, q_i, jacobians[0]);
    }
    if (jacobians[1] != nullptr) {
      tangent.topLeftCorner<3, 3>() = r_inv_ * r_a;
      tangent.topRightCorner<3, 3>().setZero();
      tangent.bottomLeftCorner<3, 3>().setZero();
      tangent.bottomRightCorner<3, 3>() = m;
      ToAmbient(sqrt_information_ * tangent, q_j, jacobians[1]);
    }
    return true;
  }

 private:
  // out (6x7, row-major) = tangent * P^+, P^+ = [R^T 0; 0 4 Q^T] with
  // Q = 1/2 [w I + [v]x; -v^T] (rows x, y, z, w): 4 Q^T = 2 [w I - [v]x, -v].
  static void ToAmbient(const Eigen::Matrix<double, 6, 6>& tangent,
                        const Eigen::Quaterniond& q, double* out) {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> j(out);
    j.leftCols<3>() = tangent.leftCols<3>() * q.toRotationMatrix().transpose();
    Eigen::Matrix<double, 3, 4> q_pinv;
    q_pinv.leftCols<3>() =
        2.0 * (q.w() * Eigen::Matrix3d::Identity() - Skew<double>(q.vec()));
    q_pinv.col(3) = -2.0 * q.vec();
    j.rightCols<4>() = tangent.rightCols<3>() * q_pinv;
  }

  Eigen::Vector3d t_inv_;     // Translation of Z_ij^-1.
  Eigen::Quaterniond q_inv_;  // Rotation of Z_ij^-1.
  Eigen::Matrix3d r_inv_;     // Its matrix.
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

inline ceres::CostFunction* BetweenSE3Factor::Create(
    const Eigen::Vector3d& t_measured, const Eigen::Quaterniond& q_measured,
    const Eigen::Matrix<double, 6, 6>& sqrt_information) {
  return new BetweenSE3CostFunction(t_measured, q_measured, sqrt_information);
}

}  // namespace slam

#endif  // SLAM_FACTORS_BETWEEN_SE3_H_
