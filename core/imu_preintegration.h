// On-manifold IMU preintegration (Forster, Carlone, Dellaert, Scaramuzza,
// "On-Manifold Preintegration for Real-Time Visual-Inertial Odometry",
// IEEE T-RO 2017).
//
// States and frames
//   Body frame B = IMU frame. Pose X = (p, R) maps body to world (p: body
//   origin in the world, R = R_WB), velocity v of the body origin in the world
//   frame, bias b = (bg, ba): gyroscope bias then accelerometer bias, both in
//   the body frame (node kinds kPose3, kVelocity3, kImuBias of core/keys.h).
// Sensor model
//   gyro  = omega_B + bg + ng,        omega_B: body angular rate,
//   accel = R^T (a_W - g) + ba + na,  a_W: world acceleration, g: gravity
//   (default (0, 0, -9.81): world z up; a resting IMU reads +9.81 on z).
//
// Preintegrated increments between keyframes i and j (bias fixed at the
// linearization point b_bar, written b in the following):
//   dR_ij = prod_k Exp((gyro_k - bg) dt_k)
//   dv_ij = sum_k dR_ik (accel_k - ba) dt_k
//   dp_ij = sum_k dv_ik dt_k + 1/2 dR_ik (accel_k - ba) dt_k^2
// They relate the states as
//   R_j = R_i dR_ij
//   v_j = v_i + g dt_ij + R_i dv_ij
//   p_j = p_i + v_i dt_ij + 1/2 g dt_ij^2 + R_i dp_ij.
//
// Integration scheme (Integrate): MIDPOINT in rotation. Each call takes one
// reading held over the interval dt (pass the reading at the middle of the
// interval, or the mean of the readings at its ends, for second-order
// accuracy) and applies it with the rotation at the middle of the interval,
// dR_half = dR Exp(w dt / 2):
//   dp += dv dt + 1/2 dR_half a dt^2,  dv += dR_half a dt,  dR = dR Exp(w dt).
// Forster's paper uses the rotation at the start of the interval (Euler);
// the midpoint rotation makes the scheme second order in dt for smooth
// motion (global error O(dt^2); the rotation is exact for a constant rate).
// It is exact, to rounding, for motion whose body rate and world
// acceleration are constant over each interval (a geodesic rotation spline
// and a C1 quadratic position spline with knots at the samples), given the
// readings at the interval middles.
//
// Tangent order and perturbation side
//   The preintegrated error state is [dphi, dv, dp] (rotation, velocity,
//   position: Forster's order, 9 values), with a RIGHT perturbation of the
//   rotation, dR_true = dR Exp(dphi), as the SE(3) manifold of
//   core/conventions.h uses. Note the ORDER differs from the SE(3) pose
//   tangent (translation first, then rotation): the IMU factor residual is
//   (rotation, velocity, position), matching covariance() here; the Jacobians
//   Ceres forms with respect to the pose block are in the manifold's
//   (translation, rotation) order as usual.
// Covariance
//   covariance() is the 9x9 covariance over [dphi, dv, dp] propagated with
//   Sigma' = A Sigma A^T + B Q B^T, Q = diag(sigma_g^2 / dt I3, sigma_a^2 / dt
//   I3): the continuous-time noise densities of ImuNoise turned into the
//   discrete per-sample covariance density^2 / dt, plus sigma_a^2 dt^3 / 12
//   I3 on dp per reading: the position effect of the white noise within
//   the interval that the held reading misses (continuous-time white noise
//   integrated twice has variance sigma_a^2 dt^3 / 3; the held reading
//   gives dt^3 / 4). It keeps the covariance positive definite for a single
//   reading (keyframes at the IMU rate). The bias drifting WITHIN
//   [i, j) as a random walk from b_i (the factor holds b_i throughout) is
//   included: it enters like a bias change (through the input matrix) and is
//   propagated jointly, Cov(delta, beta) and Cov(beta), with the random-walk
//   densities (tests: Monte Carlo with and without drift). Its correlation
//   with the bias random-walk factor's residual b_j - b_i is not modelled
//   (GTSAM's CombinedImuFactor does, with a 15-dim joint factor); with the
//   ADIS16448 and 0.5 s keyframes the ground truth's IMU chi2 went from 15 %
//   to 6 % above its expectation (tests/imu_preintegration_test.cc, batch).
// Bias Jacobians
//   bias_jacobian() is d[dphi, dv, dp] / d[bg, ba] (9x6) at b_bar, so that
//   for a bias b = b_bar + db:
//     dR(b) ~ dR Exp(dR_dbg dbg),
//     dv(b) ~ dv + dv_dbg dbg + dv_dba dba,
//     dp(b) ~ dp + dp_dbg dbg + dp_dba dba   (dR_dba = 0).
#ifndef SLAM_CORE_IMU_PREINTEGRATION_H_
#define SLAM_CORE_IMU_PREINTEGRATION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"

namespace slam {

// IMU bias (bg, ba): gyroscope bias then accelerometer bias.
using ImuBias = Eigen::Matrix<double, 6, 1>;
using ImuVector9 = Eigen::Matrix<double, 9, 1>;
using ImuMatrix9 = Eigen::Matrix<double, 9, 9>;
using ImuMatrix96 = Eigen::Matrix<double, 9, 6>;

// Continuous-time IMU noise in datasheet / Kalibr units.
struct ImuNoise {
  double gyro_noise_density = 1.6968e-4;  // rad/s/sqrt(Hz)
  double accel_noise_density = 2.0e-3;    // m/s^2/sqrt(Hz)
  double gyro_random_walk = 1.9393e-5;    // rad/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;      // m/s^3/sqrt(Hz)

  // ADIS16448 as in the EuRoC MAV dataset sensor.yaml (the defaults above).
  static ImuNoise Adis16448() { return ImuNoise(); }
  // All four densities positive and finite.
  bool IsValid() const;
};

// The default gravity: world z up.
inline Eigen::Vector3d DefaultGravity() { return Eigen::Vector3d(0, 0, -9.81); }

// Navigation state of the body at one time (world frame).
struct NavState {
  Pose3 pose;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

class PreintegratedImu {
 public:
  // bias_lin: (bg, ba), the bias linearization point b_bar.
  explicit PreintegratedImu(const ImuNoise& noise = ImuNoise(),
                            const ImuBias& bias_lin = ImuBias::Zero(),
                            const Eigen::Vector3d& gravity = DefaultGravity());

  // Clears the increments; optionally sets a new bias linearization point.
  void Reset();
  void Reset(const ImuBias& bias_lin);

  // Adds one reading (m/s^2, rad/s, body frame) held over dt seconds with the
  // midpoint scheme described above. Returns false (and changes nothing) if
  // dt is not positive or a value is not finite.
  bool Integrate(const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro,
                 double dt);

  const Eigen::Quaterniond& delta_q() const { return delta_q_; }
  Eigen::Matrix3d delta_R() const { return delta_q_.toRotationMatrix(); }
  const Eigen::Vector3d& delta_v() const { return delta_v_; }
  const Eigen::Vector3d& delta_p() const { return delta_p_; }
  double delta_t() const { return delta_t_; }  // seconds
  int num_samples() const { return num_samples_; }

  // 9x9 over [dphi, dv, dp].
  const ImuMatrix9& covariance() const { return covariance_; }
  // 9x6: rows [dphi, dv, dp], columns [bg, ba].
  const ImuMatrix96& bias_jacobian() const { return bias_jacobian_; }
  Eigen::Matrix3d dR_dbg() const { return bias_jacobian_.block<3, 3>(0, 0); }
  Eigen::Matrix3d dv_dbg() const { return bias_jacobian_.block<3, 3>(3, 0); }
  Eigen::Matrix3d dv_dba() const { return bias_jacobian_.block<3, 3>(3, 3); }
  Eigen::Matrix3d dp_dbg() const { return bias_jacobian_.block<3, 3>(6, 0); }
  Eigen::Matrix3d dp_dba() const { return bias_jacobian_.block<3, 3>(6, 3); }

  const ImuBias& bias_lin() const { return bias_lin_; }
  const Eigen::Vector3d& gravity() const { return gravity_; }
  const ImuNoise& noise() const { return noise_; }

  // First-order bias-corrected increments for bias b (see the header top).
  Eigen::Quaterniond CorrectedDeltaQ(const ImuBias& bias) const;
  Eigen::Vector3d CorrectedDeltaV(const ImuBias& bias) const;
  Eigen::Vector3d CorrectedDeltaP(const ImuBias& bias) const;

  // State at j predicted from the state at i and the bias (bias-corrected).
  NavState Predict(const NavState& state_i, const ImuBias& bias) const;

  // The IMU factor error e = (r_R, r_v, r_p) (not whitened), see
  // factors/imu_factor.h; computed in doubles for diagnostics and tests.
  ImuVector9 Error(const NavState& state_i, const ImuBias& bias_i,
                   const NavState& state_j) const;

 private:
  ImuNoise noise_;
  ImuBias bias_lin_;
  Eigen::Vector3d gravity_;

  Eigen::Quaterniond delta_q_;
  Eigen::Vector3d delta_v_;
  Eigen::Vector3d delta_p_;
  double delta_t_ = 0.0;
  int num_samples_ = 0;
  ImuMatrix9 covariance_;
  ImuMatrix96 bias_jacobian_;
  ImuMatrix96 drift_cross_;                       // Cov(delta, beta).
  Eigen::Matrix<double, 6, 6> drift_covariance_;  // Cov(beta).
};

// The IMU factor error e = (r_R, r_v, r_p) for the states in node storage
// form (pose: t, q xyzw; velocity: 3; bias: bg, ba), with db = b_i - b_bar:
//   r_R = Log((dR Exp(dR_dbg dbg))^T R_i^T R_j)
//   r_v = R_i^T (v_j - v_i - g dt) - (dv + dv_dbg dbg + dv_dba dba)
//   r_p = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2)
//         - (dp + dp_dbg dbg + dp_dba dba).
// Templated so that factors/imu_factor.h differentiates the same code.
template <typename T>
Eigen::Matrix<T, 9, 1> ImuError(const PreintegratedImu& pim, const T* pose_i,
                                const T* vel_i, const T* bias_i,
                                const T* pose_j, const T* vel_j) {
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  Eigen::Map<const Vec3> p_i(pose_i);
  Eigen::Map<const Eigen::Quaternion<T>> q_i(pose_i + 3);
  Eigen::Map<const Vec3> p_j(pose_j);
  Eigen::Map<const Eigen::Quaternion<T>> q_j(pose_j + 3);
  Eigen::Map<const Vec3> v_i(vel_i);
  Eigen::Map<const Vec3> v_j(vel_j);
  Eigen::Map<const Eigen::Matrix<T, 6, 1>> b_i(bias_i);
  const Eigen::Matrix<T, 6, 1> db = b_i - pim.bias_lin().cast<T>();
  const Vec3 dbg = db.template head<3>();
  const Vec3 dba = db.template tail<3>();
  const ImuMatrix96& jac = pim.bias_jacobian();

  const Vec3 phi_corr = jac.block<3, 3>(0, 0).cast<T>() * dbg;
  const Eigen::Quaternion<T> dq_corr =
      pim.delta_q().cast<T>() * QuaternionExp<T>(phi_corr);
  const Vec3 dv_corr = pim.delta_v().cast<T>() +
                       jac.block<3, 3>(3, 0).cast<T>() * dbg +
                       jac.block<3, 3>(3, 3).cast<T>() * dba;
  const Vec3 dp_corr = pim.delta_p().cast<T>() +
                       jac.block<3, 3>(6, 0).cast<T>() * dbg +
                       jac.block<3, 3>(6, 3).cast<T>() * dba;

  const T dt(pim.delta_t());
  const Vec3 g = pim.gravity().cast<T>();
  const Eigen::Quaternion<T> q_i_inv = q_i.conjugate();
  Eigen::Matrix<T, 9, 1> e;
  e.template segment<3>(0) =
      QuaternionLog<T>(dq_corr.conjugate() * (q_i_inv * q_j));
  e.template segment<3>(3) = q_i_inv * (v_j - v_i - g * dt) - dv_corr;
  e.template segment<3>(6) =
      q_i_inv * (p_j - p_i - v_i * dt - T(0.5) * g * dt * dt) - dp_corr;
  return e;
}

// One IMU reading at a stamp (body frame): accelerometer [m/s^2], gyroscope
// [rad/s].
struct ImuSample {
  TimeNs stamp = 0;
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
};

// How readings between sample stamps are modelled.
enum class ImuInterpolation {
  kLinear,  // Linear in time between samples (samples AT their stamps, as
            // real IMUs and EuRoC files deliver them): second order.
  kHold,    // Each sample held until the next stamp (a sample covers
            // [stamp, next stamp), as GTSAM's ImuFactorsExample integrates
            // the rows of its CSV file).
};

// Integrates the readings over [t_begin, t_end] into *pim (appending to what
// it holds). `samples` must be sorted by stamp (strictly increasing). The
// interval is cut at every sample stamp inside it; with kLinear each piece
// is integrated with the interpolated reading at its middle, i.e. the mean
// of its end readings; with kHold with the sample at or before its start.
// Outside the samples' span the first / last reading is held. Keyframe
// stamps need not coincide with sample stamps.
// False (and *pim untouched) when t_end <= t_begin, there is no sample, or a
// reading is not finite.
bool IntegrateImuSamples(
    const std::vector<ImuSample>& samples, TimeNs t_begin, TimeNs t_end,
    PreintegratedImu* pim,
    ImuInterpolation interpolation = ImuInterpolation::kLinear);

// RightJacobianSO3 and RightJacobianInverseSO3 live in core/lie.h.

}  // namespace slam

#endif  // SLAM_CORE_IMU_PREINTEGRATION_H_
