#include "datasets/inertial_trajectory.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace slam {

TrajectorySample LissajousTrajectory::Evaluate(double t) const {
  const LissajousParams& p = params_;
  TrajectorySample s;
  Eigen::Vector3d position;
  for (int k = 0; k < 3; ++k) {
    const double w = p.frequency[k];
    const double arg = w * t + p.phase[k];
    position[k] = p.center[k] + p.amplitude[k] * std::sin(arg);
    s.velocity[k] = p.amplitude[k] * w * std::cos(arg);
    s.acceleration[k] = -p.amplitude[k] * w * w * std::sin(arg);
  }
  const double yaw =
      p.yaw_rate * t + p.yaw_amplitude * std::sin(p.yaw_frequency * t);
  const double yaw_dot = p.yaw_rate + p.yaw_amplitude * p.yaw_frequency *
                                          std::cos(p.yaw_frequency * t);
  const double pitch = p.pitch_amplitude * std::sin(p.pitch_frequency * t);
  const double pitch_dot =
      p.pitch_amplitude * p.pitch_frequency * std::cos(p.pitch_frequency * t);
  const double roll_arg = p.roll_frequency * t + p.roll_phase;
  const double roll = p.roll_amplitude * std::sin(roll_arg);
  const double roll_dot =
      p.roll_amplitude * p.roll_frequency * std::cos(roll_arg);

  const Eigen::Matrix3d rz =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d ry =
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d rx =
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // R^T dR/dt = [(Ry Rx)^T yaw_dot e_z + Rx^T pitch_dot e_y + roll_dot e_x]x.
  s.omega = (ry * rx).transpose() * Eigen::Vector3d(0, 0, yaw_dot) +
            rx.transpose() * Eigen::Vector3d(0, pitch_dot, 0) +
            Eigen::Vector3d(roll_dot, 0, 0);
  s.pose = Pose3(position, Eigen::Quaterniond(rz * ry * rx));
  return s;
}

namespace {

// Cumulative uniform cubic B-spline basis B_1..B_3 at u and its first and
// second derivatives with respect to u (B_0 = 1).
void CumulativeBasis(double u, Eigen::Vector3d* b, Eigen::Vector3d* db,
                     Eigen::Vector3d* ddb) {
  const double u2 = u * u, u3 = u2 * u;
  *b << (5.0 + 3.0 * u - 3.0 * u2 + u3) / 6.0,
      (1.0 + 3.0 * u + 3.0 * u2 - 2.0 * u3) / 6.0, u3 / 6.0;
  *db << (3.0 - 6.0 * u + 3.0 * u2) / 6.0, (3.0 + 6.0 * u - 6.0 * u2) / 6.0,
      u2 / 2.0;
  *ddb << (-6.0 + 6.0 * u) / 6.0, (6.0 - 12.0 * u) / 6.0, u;
}

}  // namespace

bool SplineTrajectory::Fit(const std::vector<StampedPose>& poses,
                           bool y_down_world, std::string* error) {
  if (poses.size() < 4) {
    *error = "a spline trajectory needs at least 4 poses";
    return false;
  }
  for (size_t k = 1; k < poses.size(); ++k) {
    if (poses[k].stamp <= poses[k - 1].stamp) {
      *error =
          "pose stamps must increase strictly (pose " + std::to_string(k) + ")";
      return false;
    }
  }
  Eigen::Matrix3d world = Eigen::Matrix3d::Identity();
  if (y_down_world) {
    // (x right, y down, z forward) -> (x forward, y left, z up).
    world << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  }
  const Eigen::Quaterniond world_q(world);
  const size_t n = poses.size();
  const double t_first = NsToSeconds(poses.front().stamp);
  const double span = NsToSeconds(poses.back().stamp - poses.front().stamp);
  knot_spacing_ = span / static_cast<double>(n - 1);
  positions_.clear();
  rotations_.clear();
  omegas_.clear();
  size_t seg = 0;
  for (size_t k = 0; k < n; ++k) {
    const double t = t_first + knot_spacing_ * static_cast<double>(k);
    while (seg + 2 < n && NsToSeconds(poses[seg + 1].stamp) <= t) ++seg;
    const StampedPose& a = poses[seg];
    const StampedPose& b = poses[seg + 1];
    const double ta = NsToSeconds(a.stamp), tb = NsToSeconds(b.stamp);
    const double w = std::clamp((t - ta) / (tb - ta), 0.0, 1.0);
    positions_.push_back(world * ((1.0 - w) * a.pose.t + w * b.pose.t));
    Eigen::Quaterniond q = world_q * a.pose.q.slerp(w, b.pose.q);
    if (!rotations_.empty() && rotations_.back().dot(q) < 0.0) {
      q.coeffs() = -q.coeffs();
    }
    rotations_.push_back(q.normalized());
    omegas_.push_back(k == 0
                          ? Eigen::Vector3d::Zero()
                          : QuaternionLog<double>(
                                rotations_[k - 1].conjugate() * rotations_[k]));
  }
  duration_ = knot_spacing_ * static_cast<double>(n - 3);
  start_stamp_ = poses.front().stamp + SecondsToNs(knot_spacing_);
  return true;
}

TrajectorySample SplineTrajectory::Evaluate(double t) const {
  const double h = knot_spacing_;
  const double s = std::clamp(t, 0.0, duration_) / h;
  const int last_segment = static_cast<int>(positions_.size()) - 4;
  const int i = std::min(static_cast<int>(std::floor(s)), last_segment);
  const double u = s - i;
  Eigen::Vector3d b, db, ddb;
  CumulativeBasis(u, &b, &db, &ddb);
  TrajectorySample out;
  Eigen::Vector3d p = positions_[i];
  out.velocity.setZero();
  out.acceleration.setZero();
  Eigen::Quaterniond q = rotations_[i];
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  for (int j = 1; j <= 3; ++j) {
    const Eigen::Vector3d dc = positions_[i + j] - positions_[i + j - 1];
    p += b[j - 1] * dc;
    out.velocity += db[j - 1] / h * dc;
    out.acceleration += ddb[j - 1] / (h * h) * dc;
    const Eigen::Vector3d& w = omegas_[i + j];
    const Eigen::Quaterniond a = QuaternionExp<double>(b[j - 1] * w);
    q = q * a;
    omega = a.conjugate() * omega + db[j - 1] / h * w;
  }
  out.pose = Pose3(p, q);
  out.omega = omega;
  return out;
}

}  // namespace slam
