#include "factors/imu_factor.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"
#include "core/manifolds.h"

namespace slam {
namespace {

using RowMajor97 = Eigen::Matrix<double, 9, 7, Eigen::RowMajor>;
using RowMajor93 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
using RowMajor96 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;
using Matrix96 = Eigen::Matrix<double, 9, 6>;

// Ambient (7) Jacobian from the tangent (6) one: J_amb = J_tan P^+ with P
// the SE(3) manifold's PlusJacobian (7x6). P^T P = diag(I3, I3 / 4) for a
// unit quaternion, so P^+ = diag(I3, 4 I3) P^T and J_amb P = J_tan.
void AmbientFromTangent(const double* pose, const Matrix96& tangent,
                        double* ambient) {
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
  SE3Manifold().PlusJacobian(pose, plus.data());
  Eigen::Matrix<double, 6, 7> pinv = plus.transpose();
  pinv.bottomRows<3>() *= 4.0;
  Eigen::Map<RowMajor97> out(ambient);
  out = tangent * pinv;
}

}  // namespace

ImuCostFunction::ImuCostFunction(const PreintegratedImu& pim,
                                 const ImuMatrix9& sqrt_information)
    : pim_(pim), sqrt_information_(sqrt_information) {}

bool ImuCostFunction::Evaluate(double const* const* parameters,
                               double* residuals, double** jacobians) const {
  const double* pose_i = parameters[0];
  const double* vel_i = parameters[1];
  const double* bias_i = parameters[2];
  const double* pose_j = parameters[3];
  const double* vel_j = parameters[4];
  const ImuVector9 e =
      ImuError<double>(pim_, pose_i, vel_i, bias_i, pose_j, vel_j);
  Eigen::Map<ImuVector9> r(residuals);
  r = sqrt_information_ * e;
  if (jacobians == nullptr) return true;

  // Tangent Jacobians of e (rows r_R, r_v, r_p), see the header.
  const Eigen::Map<const Eigen::Vector3d> p_i(pose_i), p_j(pose_j);
  const Eigen::Quaterniond q_i(
      Eigen::Map<const Eigen::Quaterniond>(pose_i + 3));
  const Eigen::Quaterniond q_j(
      Eigen::Map<const Eigen::Quaterniond>(pose_j + 3));
  const Eigen::Map<const Eigen::Vector3d> v_i(vel_i), v_j(vel_j);
  const Eigen::Matrix3d r_i_t = q_i.toRotationMatrix().transpose();
  const Eigen::Matrix3d r_j = q_j.toRotationMatrix();
  const ImuMatrix96& jb = pim_.bias_jacobian();
  const Eigen::Vector3d dbg =
      Eigen::Map<const Eigen::Vector3d>(bias_i) - pim_.bias_lin().head<3>();
  const double dt = pim_.delta_t();
  const Eigen::Vector3d& g = pim_.gravity();
  const Eigen::Vector3d r_rot = e.head<3>();
  const Eigen::Matrix3d jr_inv = RightJacobianInverseSO3(r_rot);
  const Eigen::Vector3d v_term = r_i_t * (v_j - v_i - g * dt);
  const Eigen::Vector3d p_term =
      r_i_t * (p_j - p_i - v_i * dt - 0.5 * g * dt * dt);

  if (jacobians[0] != nullptr) {  // pose_i: (rho_i, phi_i)
    Matrix96 j = Matrix96::Zero();
    j.block<3, 3>(0, 3) = -jr_inv * r_j.transpose() * r_i_t.transpose();
    j.block<3, 3>(3, 3) = Skew<double>(v_term);
    j.block<3, 3>(6, 0) = -Eigen::Matrix3d::Identity();
    j.block<3, 3>(6, 3) = Skew<double>(p_term);
    AmbientFromTangent(pose_i, sqrt_information_ * j, jacobians[0]);
  }
  if (jacobians[1] != nullptr) {  // vel_i
    Eigen::Matrix<double, 9, 3> j = Eigen::Matrix<double, 9, 3>::Zero();
    j.block<3, 3>(3, 0) = -r_i_t;
    j.block<3, 3>(6, 0) = -r_i_t * dt;
    Eigen::Map<RowMajor93> out(jacobians[1]);
    out = sqrt_information_ * j;
  }
  if (jacobians[2] != nullptr) {  // bias_i: (bg, ba)
    Matrix96 j = Matrix96::Zero();
    const Eigen::Matrix3d jr_corr =
        RightJacobianSO3(jb.block<3, 3>(0, 0) * dbg);
    j.block<3, 3>(0, 0) =
        -jr_inv * QuaternionExp<double>(r_rot).toRotationMatrix().transpose() *
        jr_corr * jb.block<3, 3>(0, 0);
    j.block<6, 6>(3, 0) = -jb.block<6, 6>(3, 0);
    Eigen::Map<RowMajor96> out(jacobians[2]);
    out = sqrt_information_ * j;
  }
  if (jacobians[3] != nullptr) {  // pose_j: (rho_j, phi_j)
    Matrix96 j = Matrix96::Zero();
    j.block<3, 3>(0, 3) = jr_inv;
    j.block<3, 3>(6, 0) = r_i_t * r_j;
    AmbientFromTangent(pose_j, sqrt_information_ * j, jacobians[3]);
  }
  if (jacobians[4] != nullptr) {  // vel_j
    Eigen::Matrix<double, 9, 3> j = Eigen::Matrix<double, 9, 3>::Zero();
    j.block<3, 3>(3, 0) = r_i_t;
    Eigen::Map<RowMajor93> out(jacobians[4]);
    out = sqrt_information_ * j;
  }
  return true;
}

}  // namespace slam
