#include "core/imu_preintegration.h"

#include <algorithm>
#include <cmath>

namespace slam {
namespace {

bool PositiveFinite(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

bool ImuNoise::IsValid() const {
  return PositiveFinite(gyro_noise_density) &&
         PositiveFinite(accel_noise_density) &&
         PositiveFinite(gyro_random_walk) && PositiveFinite(accel_random_walk);
}

PreintegratedImu::PreintegratedImu(const ImuNoise& noise,
                                   const ImuBias& bias_lin,
                                   const Eigen::Vector3d& gravity)
    : noise_(noise), bias_lin_(bias_lin), gravity_(gravity) {
  Reset();
}

void PreintegratedImu::Reset() {
  delta_q_.setIdentity();
  delta_v_.setZero();
  delta_p_.setZero();
  delta_t_ = 0.0;
  num_samples_ = 0;
  covariance_.setZero();
  bias_jacobian_.setZero();
  drift_cross_.setZero();
  drift_covariance_.setZero();
}

void PreintegratedImu::Reset(const ImuBias& bias_lin) {
  bias_lin_ = bias_lin;
  Reset();
}

bool PreintegratedImu::Integrate(const Eigen::Vector3d& accel,
                                 const Eigen::Vector3d& gyro, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt) || !accel.allFinite() ||
      !gyro.allFinite()) {
    return false;
  }
  const Eigen::Vector3d w = gyro - bias_lin_.head<3>();
  const Eigen::Vector3d a = accel - bias_lin_.tail<3>();
  const Eigen::Matrix3d r = delta_q_.toRotationMatrix();
  const Eigen::Quaterniond e_q = QuaternionExp<double>(w * dt);
  const Eigen::Quaterniond e_half_q = QuaternionExp<double>(w * (0.5 * dt));
  const Eigen::Matrix3d e = e_q.toRotationMatrix();
  const Eigen::Matrix3d e_half = e_half_q.toRotationMatrix();
  const Eigen::Matrix3d r_half = r * e_half;
  const Eigen::Matrix3d jr = RightJacobianSO3(w * dt);
  const Eigen::Matrix3d jr_half = RightJacobianSO3(w * (0.5 * dt));
  const Eigen::Matrix3d r_half_a_skew = r_half * Skew<double>(a);
  const double dt2 = dt * dt;

  // Error-state transition over [dphi, dv, dp] ...
  ImuMatrix9 A = ImuMatrix9::Identity();
  A.block<3, 3>(0, 0) = e.transpose();
  A.block<3, 3>(3, 0) = -r_half_a_skew * e_half.transpose() * dt;
  A.block<3, 3>(6, 0) = -0.5 * r_half_a_skew * e_half.transpose() * dt2;
  A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;
  // ... and its input matrix over [gyro, accel] (white noise and bias enter
  // the readings identically, so B also drives the bias Jacobians).
  ImuMatrix96 B = ImuMatrix96::Zero();
  B.block<3, 3>(0, 0) = -jr * dt;
  B.block<3, 3>(3, 0) = r_half_a_skew * jr_half * (0.5 * dt2);
  B.block<3, 3>(3, 3) = -r_half * dt;
  B.block<3, 3>(6, 0) = r_half_a_skew * jr_half * (0.25 * dt2 * dt);
  B.block<3, 3>(6, 3) = -0.5 * r_half * dt2;

  Eigen::Matrix<double, 6, 1> q_diag;
  const double var_g =
      noise_.gyro_noise_density * noise_.gyro_noise_density / dt;
  const double var_a =
      noise_.accel_noise_density * noise_.accel_noise_density / dt;
  q_diag << var_g, var_g, var_g, var_a, var_a, var_a;
  // The bias drifts within [i, j) as a random walk beta from b_i (beta = 0
  // at i); it enters the deltas exactly as a bias change does, through B:
  //   delta' = A delta + B (n + beta),  beta' = beta + w.
  // Propagating the joint covariance and keeping the deltas' block gives the
  // covariance of the preintegrated measurement given b_i.
  const Eigen::Matrix<double, 9, 9> cross_term =
      A * drift_cross_ * B.transpose();
  covariance_ = A * covariance_ * A.transpose() + cross_term +
                cross_term.transpose() +
                B *
                    (drift_covariance_ +
                     Eigen::Matrix<double, 6, 6>(q_diag.asDiagonal())) *
                    B.transpose();
  // The reading is the noise averaged over the interval; the white noise
  // WITHIN it also moves the position: integrated twice over dt it has
  // variance density^2 dt^3 / 3 per axis, of which the held reading above
  // carries density^2 dt^3 / 4 (its velocity part and the velocity-position
  // correlation dt^2 / 2 are exact). Without the remaining dt^3 / 12 one
  // reading gives a rank-6 covariance (position noise a copy of velocity
  // noise), so that intervals of one or two readings (keyframe rate near the
  // IMU rate) had no valid information matrix.
  covariance_.block<3, 3>(6, 6) +=
      Eigen::Matrix3d::Identity() *
      (noise_.accel_noise_density * noise_.accel_noise_density * dt2 * dt /
       12.0);
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
  drift_cross_ = A * drift_cross_ + B * drift_covariance_;
  Eigen::Matrix<double, 6, 1> walk;
  walk << Eigen::Vector3d::Constant(noise_.gyro_random_walk *
                                    noise_.gyro_random_walk * dt),
      Eigen::Vector3d::Constant(noise_.accel_random_walk *
                                noise_.accel_random_walk * dt);
  drift_covariance_ += walk.asDiagonal();
  bias_jacobian_ = A * bias_jacobian_ + B;

  const Eigen::Vector3d a_world = r_half * a;
  delta_p_ += delta_v_ * dt + 0.5 * a_world * dt2;
  delta_v_ += a_world * dt;
  delta_q_ = (delta_q_ * e_q).normalized();
  delta_t_ += dt;
  ++num_samples_;
  return true;
}

Eigen::Quaterniond PreintegratedImu::CorrectedDeltaQ(
    const ImuBias& bias) const {
  const Eigen::Vector3d dbg = (bias - bias_lin_).head<3>();
  return (delta_q_ * QuaternionExp<double>(dR_dbg() * dbg)).normalized();
}

Eigen::Vector3d PreintegratedImu::CorrectedDeltaV(const ImuBias& bias) const {
  const ImuBias db = bias - bias_lin_;
  return delta_v_ + dv_dbg() * db.head<3>() + dv_dba() * db.tail<3>();
}

Eigen::Vector3d PreintegratedImu::CorrectedDeltaP(const ImuBias& bias) const {
  const ImuBias db = bias - bias_lin_;
  return delta_p_ + dp_dbg() * db.head<3>() + dp_dba() * db.tail<3>();
}

NavState PreintegratedImu::Predict(const NavState& state_i,
                                   const ImuBias& bias) const {
  const Eigen::Quaterniond& q_i = state_i.pose.q;
  const double dt = delta_t_;
  NavState out;
  out.pose = Pose3(state_i.pose.t + state_i.velocity * dt +
                       0.5 * gravity_ * dt * dt + q_i * CorrectedDeltaP(bias),
                   q_i * CorrectedDeltaQ(bias));
  out.velocity = state_i.velocity + gravity_ * dt + q_i * CorrectedDeltaV(bias);
  return out;
}

ImuVector9 PreintegratedImu::Error(const NavState& state_i,
                                   const ImuBias& bias_i,
                                   const NavState& state_j) const {
  double xi[7], xj[7];
  Eigen::Map<Eigen::Matrix<double, 7, 1>> map_i(xi), map_j(xj);
  map_i << state_i.pose.t, state_i.pose.q.coeffs();
  map_j << state_j.pose.t, state_j.pose.q.coeffs();
  return ImuError<double>(*this, xi, state_i.velocity.data(), bias_i.data(), xj,
                          state_j.velocity.data());
}

namespace {

// Reading at time t, linearly interpolated between the samples around it
// (held constant outside the sample range).
void InterpolatedReading(const std::vector<ImuSample>& samples, TimeNs t,
                         Eigen::Vector3d* accel, Eigen::Vector3d* gyro) {
  const auto it = std::upper_bound(
      samples.begin(), samples.end(), t,
      [](TimeNs s, const ImuSample& sample) { return s < sample.stamp; });
  if (it == samples.begin()) {
    *accel = it->accel;
    *gyro = it->gyro;
    return;
  }
  if (it == samples.end()) {
    *accel = samples.back().accel;
    *gyro = samples.back().gyro;
    return;
  }
  const ImuSample& a = *(it - 1);
  const ImuSample& b = *it;
  const double u =
      static_cast<double>(t - a.stamp) / static_cast<double>(b.stamp - a.stamp);
  *accel = (1.0 - u) * a.accel + u * b.accel;
  *gyro = (1.0 - u) * a.gyro + u * b.gyro;
}

}  // namespace

bool IntegrateImuSamples(const std::vector<ImuSample>& samples, TimeNs t_begin,
                         TimeNs t_end, PreintegratedImu* pim,
                         ImuInterpolation interpolation) {
  if (t_end <= t_begin || samples.empty()) return false;
  // Cut points: t_begin, the sample stamps strictly inside, t_end.
  std::vector<TimeNs> cuts = {t_begin};
  auto it = std::upper_bound(
      samples.begin(), samples.end(), t_begin,
      [](TimeNs s, const ImuSample& sample) { return s < sample.stamp; });
  for (; it != samples.end() && it->stamp < t_end; ++it) {
    cuts.push_back(it->stamp);
  }
  cuts.push_back(t_end);
  PreintegratedImu result = *pim;
  Eigen::Vector3d a0, g0, a1, g1;
  InterpolatedReading(samples, cuts[0], &a0, &g0);
  for (size_t k = 1; k < cuts.size(); ++k) {
    const double dt = NsToSeconds(cuts[k] - cuts[k - 1]);
    bool ok;
    if (interpolation == ImuInterpolation::kHold) {
      auto at = std::upper_bound(
          samples.begin(), samples.end(), cuts[k - 1],
          [](TimeNs s, const ImuSample& sample) { return s < sample.stamp; });
      if (at != samples.begin()) --at;  // The last sample at or before.
      ok = result.Integrate(at->accel, at->gyro, dt);
    } else {
      InterpolatedReading(samples, cuts[k], &a1, &g1);
      ok = result.Integrate(0.5 * (a0 + a1), 0.5 * (g0 + g1), dt);
      a0 = a1;
      g0 = g1;
    }
    if (!ok) return false;
  }
  *pim = result;
  return true;
}

}  // namespace slam
