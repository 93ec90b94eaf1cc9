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
// Jacobians: automatic differentiation of ImuError.
#ifndef SLAM_FACTORS_IMU_FACTOR_H_
#define SLAM_FACTORS_IMU_FACTOR_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "core/imu_preintegration.h"

namespace slam {

class ImuFactor {
public:
  ImuFactor(const PreintegratedImu &pim, const ImuMatrix9 &sqrt_information)
      : pim_(pim), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T *const pose_i, const T *const vel_i,
                  const T *const bias_i, const T *const pose_j,
                  const T *const vel_j, T *residual) const {
    const Eigen::Matrix<T, 9, 1> e =
        ImuError<T>(pim_, pose_i, vel_i, bias_i, pose_j, vel_j);
    Eigen::Map<Eigen::Matrix<T, 9, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction *Create(const PreintegratedImu &pim,
                                     const ImuMatrix9 &sqrt_information) {
    return new ceres::AutoDiffCostFunction<ImuFactor, 9, 7, 3, 6, 7, 3>(
        new ImuFactor(pim, sqrt_information));
  }

private:
  PreintegratedImu pim_;
  ImuMatrix9 sqrt_information_;
};

} // namespace slam

#endif // SLAM_FACTORS_IMU_FACTOR_H_
