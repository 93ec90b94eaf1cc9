// Consistency of inertial estimates: NEES (normalised estimation error
// squared) of keyframe states against ground truth (pose, velocity, bias),
// under the covariance the estimator reports
// (InertialRun::newest_covariance: the sliding window's joint marginal of the
// newest keyframe right after its update).
//
// Definition. Estimate x = (T, v, b), T = (t, R) body to world, v world
// velocity, b = (bg, ba); covariance P (15 x 15) over the tangent
// (rho, phi, dv, dbg, dba) of core/conventions.h: RIGHT (body-frame)
// perturbation, translation first, full angle, i.e. x [+] e =
// (t + R rho, R Exp(phi), v + dv, b + db). The error is the tangent vector
// that moves the estimate onto the truth x* (truth = x [+] e):
//   rho = R^T (t* - t),  phi = Log(R^T R*),  dv = v* - v,  db = b* - b.
// The NEES of a block of e is e_B^T (P_BB)^-1 e_B with P_BB the block's
// marginal covariance (the rows/columns of P for B):
//   position  rho        3 dof  (the same as the world-frame error under the
//                                world-frame covariance R P_rr R^T)
//   pose      rho, phi   6 dof
//   velocity  dv         3 dof
//   bias      dbg, dba   6 dof (and each alone: gyro_bias, accel_bias, 3)
// For a consistent estimator with Gaussian errors each is chi2(dof)
// distributed: mean = dof over many keyframes/runs. Larger means an
// overconfident covariance (or biased estimate), smaller a conservative one.
//
// Ground-truth rotation offset: a reference whose attitude is off by a
// constant yaw (EuRoC's V1_02 ground truth is about 1.3 deg off against the
// IMU) adds that error to phi, which a covariance of a few tenths of a degree
// turns into a large pose NEES even for a perfect estimator.
// EstimateYawOffset measures the constant world-frame yaw psi that best maps
// the reference rotations onto the estimate's (R ~ Rz(psi) R*, mean over the
// keyframes), and NeesOptions::yaw_offset applies it to the reference before
// the errors are taken (R* -> Rz(psi) R*; positions, velocities and biases
// unchanged). This removes one constant degree of freedom fitted on the same
// keyframes, so it is reported beside, never instead of, the raw NEES.
#ifndef SLAM_FRONTENDS_INERTIAL_INERTIAL_CONSISTENCY_H_
#define SLAM_FRONTENDS_INERTIAL_INERTIAL_CONSISTENCY_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/sensors/inertial_data.h"
#include "frontends/inertial/inertial_estimator.h"

namespace slam {

// The error e (15: rho, phi, dv, dbg, dba) of `estimate` against `truth`
// (definition above).
Eigen::Matrix<double, 15, 1> InertialStateError(
    const InertialState& estimate, const InertialGroundTruth& truth);

struct InertialNees {
  double position = 0.0;    // 3 dof
  double pose = 0.0;        // 6 dof
  double velocity = 0.0;    // 3 dof
  double bias = 0.0;        // 6 dof
  double gyro_bias = 0.0;   // 3 dof, dbg alone
  double accel_bias = 0.0;  // 3 dof, dba alone
};

// NEES of each block of `error` under the 15 x 15 `covariance`. False when a
// block's covariance is not positive definite.
bool ComputeInertialNees(const Eigen::Matrix<double, 15, 1>& error,
                         const Eigen::MatrixXd& covariance, InertialNees* nees);

// The reference state at `stamp`: linear interpolation between the two
// bracketing entries (position, velocity, bias; slerp for the rotation).
// False when `stamp` is outside the reference or the bracketing entries are
// more than `max_gap` apart.
bool InterpolateGroundTruth(const std::vector<InertialGroundTruth>& reference,
                            TimeNs stamp, TimeNs max_gap,
                            InertialGroundTruth* out);

struct NeesOptions {
  // Keyframes earlier than this after the first keyframe are left out (the
  // start-up transient of the estimator).
  double skip_seconds = 10.0;
  TimeNs max_gap = 200000000;  // Reference interpolation, 0.2 s.
  double yaw_offset = 0.0;     // radians, applied to the reference rotation.
};

struct NeesStats {
  double mean = 0.0;
  double median = 0.0;
};

struct NeesSummary {
  int keyframes = 0;  // Keyframes evaluated (after skip, with a reference).
  NeesStats position, pose, velocity, bias, gyro_bias, accel_bias;
  std::vector<TimeNs> stamps;  // Per evaluated keyframe.
  std::vector<InertialNees> per_keyframe;
  // Root mean square of the rotation error |phi| over the same keyframes
  // (radians; under options.yaw_offset when set).
  double rotation_rmse = 0.0;
};

// NEES of every state (with its covariance, the same order) against the
// reference. False (with `error`) when the sizes differ, no keyframe is left
// to evaluate, or a covariance is not positive definite.
bool SummarizeNees(const std::vector<InertialState>& states,
                   const std::vector<Eigen::MatrixXd>& covariances,
                   const std::vector<InertialGroundTruth>& reference,
                   const NeesOptions& options, NeesSummary* summary,
                   std::string* error);

// The constant world-frame yaw psi with R ~ Rz(psi) R* over the states
// evaluated under `options` (circular mean of the yaw of R R*^T).
double EstimateYawOffset(const std::vector<InertialState>& states,
                         const std::vector<InertialGroundTruth>& reference,
                         const NeesOptions& options);

}  // namespace slam

#endif  // SLAM_FRONTENDS_INERTIAL_INERTIAL_CONSISTENCY_H_
