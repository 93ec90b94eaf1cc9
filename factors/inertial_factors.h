// Builders of the inertial factors as graph Factors (cost function,
// measurement and information kept together). The autodiff cost functions of
// factors/imu_factor.h, bias_random_walk.h, position_factor.h and
// euclidean_prior.h are instantiated in inertial_factors.cc only.
//
// Stored measurement and information per FactorType:
//   kImu:            (dq xyzw (4), dv (3), dp (3), dt seconds (1)); information
//                    = covariance()^-1, 9x9 over (rotation, velocity,
//                    position).
//   kBiasRandomWalk: zero (6); information diag(1/(sigma_g^2 dt) I3,
//                    1/(sigma_a^2 dt) I3) over (bg, ba).
//   kPosition:       (z (3), lever arm (3)); information 3x3 (world frame).
//   kPriorVelocity:  v (3); information 3x3.
//   kPriorBias:      (bg, ba) (6); information 6x6.
// Pose priors reuse MakePriorSE3 (factors/pose_factors.h); note that its
// information is over (t, quaternion vector part), i.e. HALF-angle units:
// a rotation standard deviation sigma (rad) is an information 4 / sigma^2.
#ifndef SLAM_FACTORS_INERTIAL_FACTORS_H_
#define SLAM_FACTORS_INERTIAL_FACTORS_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/conventions.h"
#include "core/graph.h"
#include "core/imu_preintegration.h"
#include "core/keys.h"

namespace slam {

// Fails when the preintegration holds no sample or its covariance is not
// positive definite (one reading alone gives a rank-6 covariance: velocity
// and position noise are then perfectly correlated; integrate two or more).
bool MakeImuFactor(const Key& pose_i, const Key& vel_i, const Key& bias_i,
                   const Key& pose_j, const Key& vel_j,
                   const PreintegratedImu& pim, Factor* factor,
                   std::string* error);

// Random walk over dt seconds (dt > 0) with the densities of `noise`.
bool MakeBiasRandomWalk(const Key& bias_i, const Key& bias_j,
                        const ImuNoise& noise, double dt, Factor* factor,
                        std::string* error);

// World position z of the point at lever_arm in the body frame.
bool MakePositionFactor(const Key& pose, const Eigen::Vector3d& z,
                        const Eigen::Matrix3d& information,
                        const Eigen::Vector3d& lever_arm, Factor* factor,
                        std::string* error);

bool MakePriorVelocity(const Key& velocity, const Eigen::Vector3d& z,
                       const Eigen::Matrix3d& information, Factor* factor,
                       std::string* error);

bool MakePriorBias(const Key& bias, const ImuBias& z,
                   const Eigen::Matrix<double, 6, 6>& information,
                   Factor* factor, std::string* error);

// Adds the three nodes of an inertial state at `stamp`: Pose3Key(id),
// VelocityKey(id) and ImuBiasKey(id), all with has_stamp. False (and no
// node added) if any of the keys exists.
bool AddInertialState(Graph* graph, int64_t id, TimeNs stamp,
                      const NavState& state, const ImuBias& bias);

// The state and bias stored in the nodes of AddInertialState; false if a
// node is missing.
bool GetInertialState(const Graph& graph, int64_t id, NavState* state,
                      ImuBias* bias);

// Square-root information of a covariance: a matrix S with
// S^T S = covariance^-1 (S = C^-1 for covariance = C C^T), so that r = S e
// has |r|^2 = e^T covariance^-1 e. False if not positive definite.
bool SqrtInformationFromCovariance(const Eigen::MatrixXd& covariance,
                                   Eigen::MatrixXd* sqrt_information);

}  // namespace slam

#endif  // SLAM_FACTORS_INERTIAL_FACTORS_H_
