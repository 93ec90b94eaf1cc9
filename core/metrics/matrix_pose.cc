#include "core/metrics/matrix_pose.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Geometry>

namespace slam {

MatrixPose::MatrixPose(const Pose3& pose) : t(pose.t) {
  // transformations.quaternion_matrix: q *= sqrt(2 / |q|^2), then the
  // entries of the outer product q q^T (q = w, x, y, z).
  const Eigen::Quaterniond& q = pose.q;
  double v[4] = {q.w(), q.x(), q.y(), q.z()};
  const double n = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3];
  if (n < std::numeric_limits<double>::epsilon() * 4.0) return;
  const double f = std::sqrt(2.0 / n);
  for (double& x : v) x *= f;
  auto o = [&](int i, int j) { return v[i] * v[j]; };
  r << 1.0 - o(2, 2) - o(3, 3), o(1, 2) - o(3, 0), o(1, 3) + o(2, 0),
      o(1, 2) + o(3, 0), 1.0 - o(1, 1) - o(3, 3), o(2, 3) - o(1, 0),
      o(1, 3) - o(2, 0), o(2, 3) + o(1, 0), 1.0 - o(1, 1) - o(2, 2);
}

std::vector<MatrixPose> ToMatrixPoses(const std::vector<Pose3>& poses) {
  std::vector<MatrixPose> out;
  out.reserve(poses.size());
  for (const Pose3& p : poses) out.emplace_back(p);
  return out;
}

double NearestSeconds(TimeNs ns) {
  // Up to 2^53 the integer is exact in a double and IEEE division rounds
  // correctly.
  constexpr TimeNs kExact = TimeNs{1} << 53;
  if (ns > -kExact && ns < kExact) return static_cast<double>(ns) / 1e9;
  // Otherwise the exact decimal text, then its correctly rounded double.
  char buf[40];
  const bool negative = ns < 0;
  const unsigned long long a = negative
                                   ? 0ULL - static_cast<unsigned long long>(ns)
                                   : static_cast<unsigned long long>(ns);
  const int len =
      std::snprintf(buf, sizeof(buf), "%s%llu.%09llu", negative ? "-" : "",
                    a / 1000000000ULL, a % 1000000000ULL);
  double value = 0.0;
  std::from_chars(buf, buf + len, value);
  return value;
}

EvalTrajectory ToEvalTrajectory(const Trajectory& trajectory) {
  EvalTrajectory out;
  out.stamps.reserve(trajectory.size());
  out.seconds.reserve(trajectory.size());
  out.poses.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) {
    out.stamps.push_back(p.stamp);
    out.seconds.push_back(NearestSeconds(p.stamp));
    out.poses.emplace_back(p.pose);
  }
  return out;
}

double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::fabs(q.w()));
}

double RotationAngleOfMatrix(const Eigen::Matrix3d& m) {
  // scipy Rotation.from_matrix (Markley 2008): the branch of the largest of
  // the diagonal entries and the trace, then normalization.
  const double trace = m(0, 0) + m(1, 1) + m(2, 2);
  int choice = 3;
  double largest = trace;
  for (int i = 0; i < 3; ++i) {
    if (m(i, i) > largest) {
      largest = m(i, i);
      choice = i;
    }
  }
  double q[4];  // x, y, z, w.
  if (choice != 3) {
    const int i = choice, j = (i + 1) % 3, k = (j + 1) % 3;
    q[i] = 1.0 - trace + 2.0 * m(i, i);
    q[j] = m(j, i) + m(i, j);
    q[k] = m(k, i) + m(i, k);
    q[3] = m(k, j) - m(j, k);
  } else {
    q[0] = m(2, 1) - m(1, 2);
    q[1] = m(0, 2) - m(2, 0);
    q[2] = m(1, 0) - m(0, 1);
    q[3] = 1.0 + trace;
  }
  const double norm =
      std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& x : q) x /= norm;
  // as_rotvec: w >= 0, angle = 2 atan2(|v|, w), rotvec = angle / sin(angle
  // / 2) * v (a series near 0); the angle returned is |rotvec|.
  if (q[3] < 0.0) {
    for (double& x : q) x = -x;
  }
  const double v = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const double angle = 2.0 * std::atan2(v, q[3]);
  const double a2 = angle * angle;
  const double scale = angle <= 1e-3 ? 2.0 + a2 / 12.0 + 7.0 * a2 * a2 / 2880.0
                                     : angle / std::sin(angle / 2.0);
  const double x = scale * q[0], y = scale * q[1], z = scale * q[2];
  return std::sqrt(x * x + y * y + z * z);
}

double PathLength(const std::vector<MatrixPose>& poses) {
  double length = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    length += (poses[i].t - poses[i - 1].t).norm();
  }
  return length;
}

double PathLength(const std::vector<Pose3>& poses) {
  return PathLength(ToMatrixPoses(poses));
}

}  // namespace slam
