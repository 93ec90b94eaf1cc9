// Small templated Lie-group helpers shared by the manifolds, the factors and
// the initializers. Everything follows core/conventions.h: Eigen quaternion
// order (x, y, z, w), full-angle rotation vectors, angles wrapped to [-pi, pi).
// The functions are templates so that Ceres Jets pass through them.
#ifndef SLAM_CORE_LIE_H_
#define SLAM_CORE_LIE_H_

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace slam {

// Wraps an angle to [-pi, pi).
template <typename T>
T NormalizeAngle(const T& angle) {
  using std::floor;
  const T two_pi(2.0 * M_PI);
  T wrapped = angle - two_pi * floor((angle + T(M_PI)) / two_pi);
  // Rounding can land one ulp outside [-pi, pi) (e.g. for pi - 1 ulp).
  if (wrapped < T(-M_PI)) wrapped += two_pi;
  if (wrapped >= T(M_PI)) wrapped -= two_pi;
  return wrapped;
}

template <typename T>
Eigen::Matrix<T, 2, 2> RotationMatrix2D(const T& theta) {
  using std::cos;
  using std::sin;
  const T c = cos(theta);
  const T s = sin(theta);
  Eigen::Matrix<T, 2, 2> r;
  r << c, -s, s, c;
  return r;
}

// Exp: full-angle rotation vector -> unit quaternion.
template <typename T>
Eigen::Quaternion<T> QuaternionExp(const Eigen::Matrix<T, 3, 1>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = phi.squaredNorm();
  T w, k;
  if (theta_sq > T(1e-12)) {
    const T theta = sqrt(theta_sq);
    w = cos(theta / 2.0);
    k = sin(theta / 2.0) / theta;
  } else {
    // Taylor expansion, exact to machine precision for theta < 1e-6; keeps
    // the derivative with respect to phi correct at zero.
    w = T(1.0) - theta_sq / 8.0;
    k = T(0.5) - theta_sq / 48.0;
  }
  return Eigen::Quaternion<T>(w, k * phi.x(), k * phi.y(), k * phi.z());
}

// Log: unit quaternion -> full-angle rotation vector with angle in [0, pi].
template <typename T>
Eigen::Matrix<T, 3, 1> QuaternionLog(const Eigen::Quaternion<T>& q_in) {
  using std::atan2;
  using std::sqrt;
  Eigen::Quaternion<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const Eigen::Matrix<T, 3, 1> v = q.vec();
  const T sin_sq = v.squaredNorm();
  if (sin_sq > T(1e-12)) {
    const T sin_half = sqrt(sin_sq);
    const T angle = T(2.0) * atan2(sin_half, q.w());
    return v * (angle / sin_half);
  }
  // 2 atan(s / w) / s ~ (2 / w) (1 - s^2 / (3 w^2)).
  return v * (T(2.0) / q.w() * (T(1.0) - sin_sq / (T(3.0) * q.w() * q.w())));
}

// Skew-symmetric (cross-product) matrix.
template <typename T>
Eigen::Matrix<T, 3, 3> Skew(const Eigen::Matrix<T, 3, 1>& v) {
  Eigen::Matrix<T, 3, 3> m;
  m << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
  return m;
}

// Plain-value pose types used by initializers, evaluation and I/O.
struct Pose2 {
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  double theta = 0.0;

  Pose2() = default;
  Pose2(double x, double y, double th) : t(x, y), theta(NormalizeAngle(th)) {}
  Pose2 operator*(const Pose2& o) const {
    return Pose2(t.x() + std::cos(theta) * o.t.x() - std::sin(theta) * o.t.y(),
                 t.y() + std::sin(theta) * o.t.x() + std::cos(theta) * o.t.y(),
                 theta + o.theta);
  }
  Pose2 Inverse() const {
    const Eigen::Vector2d ti = -RotationMatrix2D(theta).transpose() * t;
    return Pose2(ti.x(), ti.y(), -theta);
  }
};

struct Pose3 {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();

  Pose3() = default;
  Pose3(const Eigen::Vector3d& tt, const Eigen::Quaterniond& qq)
      : t(tt), q(qq.normalized()) {}
  Pose3 operator*(const Pose3& o) const { return Pose3(t + q * o.t, q * o.q); }
  Pose3 Inverse() const {
    const Eigen::Quaterniond qi = q.conjugate();
    return Pose3(-(qi * t), qi);
  }
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const {
    return t + q * p;
  }
};

// Right Jacobian of SO(3) at phi (full angle): Exp(phi + d) ~ Exp(phi)
// Exp(Jr(phi) d); and its inverse: Log(Exp(phi) Exp(d)) ~ phi + Jr^-1 d.
inline Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& phi) {
  const double theta_sq = phi.squaredNorm();
  const Eigen::Matrix3d k = Skew<double>(phi);
  if (theta_sq < 1e-10) {
    return Eigen::Matrix3d::Identity() - 0.5 * k + k * k / 6.0;
  }
  const double theta = std::sqrt(theta_sq);
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(theta)) / theta_sq * k +
         (theta - std::sin(theta)) / (theta_sq * theta) * k * k;
}

inline Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& phi) {
  const double theta_sq = phi.squaredNorm();
  const Eigen::Matrix3d k = Skew<double>(phi);
  if (theta_sq < 1e-10) {
    return Eigen::Matrix3d::Identity() + 0.5 * k + k * k / 12.0;
  }
  const double theta = std::sqrt(theta_sq);
  return Eigen::Matrix3d::Identity() + 0.5 * k +
         (1.0 / theta_sq -
          (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta))) *
             k * k;
}

}  // namespace slam

#endif  // SLAM_CORE_LIE_H_
