// IMU factor on preintegrated measurements (Forster et al., T-RO 2017).
//
// Frames and states: see core/imu_preintegration.h. Pose X = (p, R) maps the
// body (IMU) frame to the world, velocity v in the world frame, bias
// b = (bg, ba).
// Parameter blocks: pose_i (7: t, q xyzw), vel_i (3), bias_i (6),
//   pose_j (7), vel_j (3). Residuals: 9.
// Error (ImuError in core/imu_preintegration.h), order (rotation, velocity,
//   position), rotation as a full-angle rotation vector:
//   r_R = Log((dR Exp(dR_dbg dbg))^T R_i^T R_j)
//   r_v = R_i^T (v_j - v_i - g dt) - (dv + dv_dbg dbg + dv_dba dba)
//   r_p = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2) - (dp + dp_dbg dbg
//         + dp_dba dba),
//   with db = b_i - b_bar: the bias change is corrected to first order with
//   the preintegration's bias Jacobians, without re-integration.
// The bias at j is not a parameter: the preintegration only depends on the
// bias over [i, j), which is b_i; b_j enters through the bias random-walk
// factor (factors/bias_random_walk.h).
// Residual: r = L^T e with Omega = L L^T = covariance()^-1 (9x9 over
//   [dphi, dv, dp]).
// Jacobians: ImuFactor::Create differentiates ImuError automatically (the
// reference); ImuCostFunction (ImuFactor::CreateAnalytic, used by
// MakeImuFactor) has analytic ones: 2.9 us per evaluation with Jacobians
// against 19.5 us for autodiff (Release, this machine). Its Jacobians for
// the pose blocks are meant for the SE(3) manifold (core/manifolds.h):
// with P the manifold's PlusJacobian, J_ambient P equals the analytic
// tangent Jacobian (right perturbation, translation first), which is all
// Ceres uses. With e = (r_R, r_v, r_p), E = Exp(r_R), Jr^-1 = Jr^-1(r_R):
//   d r_R / d phi_i = -Jr^-1 R_j^T R_i        d r_R / d phi_j = Jr^-1
//   d r_R / d bg = -Jr^-1 E^T Jr(dR_dbg dbg) dR_dbg
//   d r_v / d phi_i = [R_i^T (v_j - v_i - g dt)]x
//   d r_v / d v_i = -R_i^T,  d r_v / d v_j = R_i^T
//   d r_v / d (bg, ba) = -(dv_dbg, dv_dba)
//   d r_p / d rho_i = -I,  d r_p / d rho_j = R_i^T R_j
//   d r_p / d phi_i = [R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2)]x
//   d r_p / d v_i = -R_i^T dt,  d r_p / d (bg, ba) = -(dp_dbg, dp_dba).
#ifndef SLAM_FACTORS_IMU_FACTOR_H_
#define SLAM_FACTORS_IMU_FACTOR_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "ceres/sized_cost_function.h"
#include "core/imu_preintegration.h"

namespace slam {

class ImuFactor {
 public:
  ImuFactor(const PreintegratedImu& pim, const ImuMatrix9& sqrt_information)
      : pim_(pim), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const pose_i, const T* const vel_i,
                  const T* const bias_i, const T* const pose_j,
                  const T* const vel_j, T* residual) const {
    const Eigen::Matrix<T, 9, 1> e =
        ImuError<T>(pim_, pose_i, vel_i, bias_i, pose_j, vel_j);
    Eigen::Map<Eigen::Matrix<T, 9, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const PreintegratedImu& pim,
                                     const ImuMatrix9& sqrt_information) {
    return new ceres::AutoDiffCostFunction<ImuFactor, 9, 7, 3, 6, 7, 3>(
        new ImuFactor(pim, sqrt_information));
  }
  // The same residual with analytic Jacobians (ImuCostFunction below).
  static ceres::CostFunction* CreateAnalytic(
      const PreintegratedImu& pim, const ImuMatrix9& sqrt_information);

 private:
  PreintegratedImu pim_;
  ImuMatrix9 sqrt_information_;
};

class ImuCostFunction : public ceres::SizedCostFunction<9, 7, 3, 6, 7, 3> {
 public:
  ImuCostFunction(const PreintegratedImu& pim,
                  const ImuMatrix9& sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  PreintegratedImu pim_;
  ImuMatrix9 sqrt_information_;
};

inline ceres::CostFunction* ImuFactor::CreateAnalytic(
    const PreintegratedImu& pim, const ImuMatrix9& sqrt_information) {
  return new ImuCostFunction(pim, sqrt_information);
}

}  // namespace slam

#endif  // SLAM_FACTORS_IMU_FACTOR_H_
