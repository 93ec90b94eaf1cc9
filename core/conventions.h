// Conventions used everywhere inside the backend. They are written down once,
// here; file readers and writers convert to and from them at the I/O boundary.
//
// Quaternions
//   Stored in Eigen's memory order (x, y, z, w), unit length, Hamilton
//   convention (i*j = k), active rotation (v_world = q * v_body * q^-1).
//   Readers normalize quaternions that are not exactly unit length (some
//   published g2o files store them so); formats that write w first (EuRoC)
//   are reordered when read.
//
// SE(2) pose node, 3 doubles: (x, y, theta), theta in radians wrapped to
//   [-pi, pi). Tangent (dx, dy, dtheta).
// SE(3) pose node, 7 doubles: (tx, ty, tz, qx, qy, qz, qw). Tangent
//   (rho_x, rho_y, rho_z, phi_x, phi_y, phi_z): translation first.
//
// Perturbation side: RIGHT (body frame) for both manifolds,
//   X [+] delta = (t + R * rho, R * Exp(phi)),
//   so tangent vectors and marginal covariances are expressed in the body
//   frame of the node, translation first, then rotation.
// Angle scale: FULL angle. Exp(phi) is the rotation by |phi| radians about
//   phi / |phi| (a quaternion (sin(|phi|/2) phi/|phi|, cos(|phi|/2))). Note
//   that g2o's 3D information matrices are expressed over the quaternion
//   vector part (about HALF the angle); that factor of two lives in the
//   residual of the SE(3) between factor, which reproduces g2o's error
//   exactly, and not in the manifold.
//
// Time: int64 nanoseconds inside (TimeNs). Seconds (double) only in files
//   that use them, converted by SecondsToNs / NsToSeconds.
//
// Cost scale: Ceres reports cost = 1/2 sum_i rho(|r_i|^2). Everything this
//   project prints or writes as "chi2" follows g2o: chi2 = sum_i e_i^T Omega_i
//   e_i, without the 1/2, i.e. chi2 = 2 * ceres_cost for non-robust factors.
//   Use CeresCostToChi2 / Chi2ToCeresCost rather than a bare factor 2.
//
// Residuals are whitened inside the cost functions: r = L^T e with
//   Omega = L L^T, so |r|^2 = e^T Omega e.
#ifndef SLAM_CORE_CONVENTIONS_H_
#define SLAM_CORE_CONVENTIONS_H_

#include <cmath>
#include <cstdint>

namespace slam {

using TimeNs = int64_t;

constexpr int64_t kNanosecondsPerSecond = 1000000000;

inline TimeNs SecondsToNs(double seconds) {
  return static_cast<TimeNs>(std::llround(seconds * 1e9));
}
inline double NsToSeconds(TimeNs ns) { return static_cast<double>(ns) * 1e-9; }

inline double CeresCostToChi2(double ceres_cost) { return 2.0 * ceres_cost; }
inline double Chi2ToCeresCost(double chi2) { return 0.5 * chi2; }

}  // namespace slam

#endif  // SLAM_CORE_CONVENTIONS_H_
