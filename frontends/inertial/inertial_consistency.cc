#include "frontends/inertial/inertial_consistency.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/lie.h"

namespace slam {
namespace {

// x^T P^-1 x for a symmetric positive definite P; false otherwise.
bool Mahalanobis(const Eigen::VectorXd& x, const Eigen::MatrixXd& p,
                 double* value) {
  const Eigen::LLT<Eigen::MatrixXd> llt(p);
  if (llt.info() != Eigen::Success) return false;
  *value = x.dot(llt.solve(x));
  return std::isfinite(*value);
}

NeesStats Stats(std::vector<double> values) {
  NeesStats s;
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) sum += v;
  s.mean = sum / values.size();
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  s.median = values[mid];
  if (values.size() % 2 == 0) {
    s.median = 0.5 * (s.median +
                      *std::max_element(values.begin(), values.begin() + mid));
  }
  return s;
}

// The states evaluated under `options` with their (yaw-corrected) reference.
template <typename Visit>
void ForEachEvaluated(const std::vector<InertialState>& states,
                      const std::vector<InertialGroundTruth>& reference,
                      const NeesOptions& options, double yaw_offset,
                      Visit visit) {
  if (states.empty()) return;
  const TimeNs first = states.front().stamp;
  const TimeNs skip = SecondsToNs(options.skip_seconds);
  const Eigen::Quaterniond yaw(
      Eigen::AngleAxisd(yaw_offset, Eigen::Vector3d::UnitZ()));
  for (size_t k = 0; k < states.size(); ++k) {
    if (states[k].stamp - first < skip) continue;
    InertialGroundTruth truth;
    if (!InterpolateGroundTruth(reference, states[k].stamp, options.max_gap,
                                &truth)) {
      continue;
    }
    truth.pose.q = (yaw * truth.pose.q).normalized();
    visit(k, truth);
  }
}

}  // namespace

Eigen::Matrix<double, 15, 1> InertialStateError(
    const InertialState& estimate, const InertialGroundTruth& truth) {
  const Pose3& x = estimate.state.pose;
  const Eigen::Quaterniond q_inv = x.q.conjugate();
  Eigen::Matrix<double, 15, 1> e;
  e.segment<3>(0) = q_inv * (truth.pose.t - x.t);
  e.segment<3>(3) = QuaternionLog<double>(q_inv * truth.pose.q);
  e.segment<3>(6) = truth.velocity - estimate.state.velocity;
  e.segment<6>(9) = truth.bias - estimate.bias;
  return e;
}

bool ComputeInertialNees(const Eigen::Matrix<double, 15, 1>& error,
                         const Eigen::MatrixXd& covariance,
                         InertialNees* nees) {
  if (covariance.rows() != 15 || covariance.cols() != 15) return false;
  return Mahalanobis(error.segment<3>(0), covariance.block(0, 0, 3, 3),
                     &nees->position) &&
         Mahalanobis(error.segment<6>(0), covariance.block(0, 0, 6, 6),
                     &nees->pose) &&
         Mahalanobis(error.segment<3>(6), covariance.block(6, 6, 3, 3),
                     &nees->velocity) &&
         Mahalanobis(error.segment<6>(9), covariance.block(9, 9, 6, 6),
                     &nees->bias) &&
         Mahalanobis(error.segment<3>(9), covariance.block(9, 9, 3, 3),
                     &nees->gyro_bias) &&
         Mahalanobis(error.segment<3>(12), covariance.block(12, 12, 3, 3),
                     &nees->accel_bias);
}

bool InterpolateGroundTruth(const std::vector<InertialGroundTruth>& reference,
                            TimeNs stamp, TimeNs max_gap,
                            InertialGroundTruth* out) {
  auto it = std::lower_bound(
      reference.begin(), reference.end(), stamp,
      [](const InertialGroundTruth& g, TimeNs t) { return g.stamp < t; });
  if (it == reference.end()) return false;
  if (it->stamp == stamp) {
    *out = *it;
    return true;
  }
  if (it == reference.begin()) return false;
  const InertialGroundTruth& a = *(it - 1);
  const InertialGroundTruth& b = *it;
  if (b.stamp - a.stamp > max_gap) return false;
  const double f = static_cast<double>(stamp - a.stamp) /
                   static_cast<double>(b.stamp - a.stamp);
  out->stamp = stamp;
  out->pose = Pose3(a.pose.t + f * (b.pose.t - a.pose.t),
                    a.pose.q.slerp(f, b.pose.q).normalized());
  out->velocity = a.velocity + f * (b.velocity - a.velocity);
  out->bias = a.bias + f * (b.bias - a.bias);
  return true;
}

bool SummarizeNees(const std::vector<InertialState>& states,
                   const std::vector<Eigen::MatrixXd>& covariances,
                   const std::vector<InertialGroundTruth>& reference,
                   const NeesOptions& options, NeesSummary* summary,
                   std::string* error) {
  *summary = NeesSummary();
  if (states.size() != covariances.size()) {
    *error = "NEES: " + std::to_string(states.size()) + " states but " +
             std::to_string(covariances.size()) + " covariances";
    return false;
  }
  bool ok = true;
  double rotation_squared = 0.0;  // Sum of |phi|^2.
  ForEachEvaluated(states, reference, options, options.yaw_offset,
                   [&](size_t k, const InertialGroundTruth& truth) {
                     InertialNees nees;
                     if (!ok) return;
                     const Eigen::Matrix<double, 15, 1> e =
                         InertialStateError(states[k], truth);
                     if (!ComputeInertialNees(e, covariances[k], &nees)) {
                       *error = "NEES: the covariance of the keyframe at " +
                                std::to_string(states[k].stamp) +
                                " ns is not positive definite";
                       ok = false;
                       return;
                     }
                     summary->stamps.push_back(states[k].stamp);
                     summary->per_keyframe.push_back(nees);
                     rotation_squared += e.segment<3>(3).squaredNorm();
                   });
  if (!ok) return false;
  if (summary->per_keyframe.empty()) {
    *error = "NEES: no keyframe with a ground-truth state after the first " +
             std::to_string(options.skip_seconds) + " s";
    return false;
  }
  std::vector<double> position, pose, velocity, bias, gyro_bias, accel_bias;
  for (const InertialNees& n : summary->per_keyframe) {
    position.push_back(n.position);
    pose.push_back(n.pose);
    velocity.push_back(n.velocity);
    bias.push_back(n.bias);
    gyro_bias.push_back(n.gyro_bias);
    accel_bias.push_back(n.accel_bias);
  }
  summary->keyframes = static_cast<int>(summary->per_keyframe.size());
  summary->rotation_rmse =
      std::sqrt(rotation_squared / summary->per_keyframe.size());
  summary->position = Stats(position);
  summary->pose = Stats(pose);
  summary->velocity = Stats(velocity);
  summary->bias = Stats(bias);
  summary->gyro_bias = Stats(gyro_bias);
  summary->accel_bias = Stats(accel_bias);
  return true;
}

double EstimateYawOffset(const std::vector<InertialState>& states,
                         const std::vector<InertialGroundTruth>& reference,
                         const NeesOptions& options) {
  double s = 0.0, c = 0.0;
  ForEachEvaluated(states, reference, options, 0.0,
                   [&](size_t k, const InertialGroundTruth& truth) {
                     const Eigen::Matrix3d d =
                         (states[k].state.pose.q * truth.pose.q.conjugate())
                             .toRotationMatrix();
                     const double yaw = std::atan2(d(1, 0), d(0, 0));
                     s += std::sin(yaw);
                     c += std::cos(yaw);
                   });
  return s == 0.0 && c == 0.0 ? 0.0 : std::atan2(s, c);
}

}  // namespace slam
