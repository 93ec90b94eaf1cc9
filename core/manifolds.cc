#include "core/manifolds.h"

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"

namespace slam {

using RowMajor33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

bool SE2Manifold::Plus(const double* x, const double* delta,
                       double* x_plus_delta) const {
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  x_plus_delta[0] = x[0] + c * delta[0] - s * delta[1];
  x_plus_delta[1] = x[1] + s * delta[0] + c * delta[1];
  x_plus_delta[2] = NormalizeAngle(x[2] + delta[2]);
  return true;
}

bool SE2Manifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajor33> j(jacobian);
  j.setZero();
  j.topLeftCorner<2, 2>() = RotationMatrix2D(x[2]);
  j(2, 2) = 1.0;
  return true;
}

bool SE2Manifold::Minus(const double* y, const double* x,
                        double* y_minus_x) const {
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  const double dx = y[0] - x[0];
  const double dy = y[1] - x[1];
  y_minus_x[0] = c * dx + s * dy;
  y_minus_x[1] = -s * dx + c * dy;
  y_minus_x[2] = NormalizeAngle(y[2] - x[2]);
  return true;
}

bool SE2Manifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajor33> j(jacobian);
  j.setZero();
  j.topLeftCorner<2, 2>() = RotationMatrix2D(x[2]).transpose();
  j(2, 2) = 1.0;
  return true;
}

bool SE3Manifold::Plus(const double* x, const double* delta,
                       double* x_plus_delta) const {
  Eigen::Map<const Eigen::Vector3d> t(x);
  const Eigen::Quaterniond q(Eigen::Map<const Eigen::Quaterniond>(x + 3));
  Eigen::Map<const Eigen::Vector3d> rho(delta);
  Eigen::Map<const Eigen::Vector3d> phi(delta + 3);
  Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  t_out = t + q * rho;
  q_out = (q * QuaternionExp<double>(phi)).normalized();
  return true;
}

bool SE3Manifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> j(jacobian);
  const Eigen::Quaterniond q(Eigen::Map<const Eigen::Quaterniond>(x + 3));
  j.setZero();
  j.block<3, 3>(0, 0) = q.toRotationMatrix();
  // d(q * Exp(phi))/dphi at 0 = 1/2 q (x) (phi, 0).
  const Eigen::Vector3d v = q.vec();
  j.block<3, 3>(3, 3) =
      0.5 * (q.w() * Eigen::Matrix3d::Identity() + Skew<double>(v));
  j.block<1, 3>(6, 3) = -0.5 * v.transpose();
  return true;
}

bool SE3Manifold::Minus(const double* y, const double* x,
                        double* y_minus_x) const {
  Eigen::Map<const Eigen::Vector3d> ty(y);
  Eigen::Map<const Eigen::Quaterniond> qy(y + 3);
  Eigen::Map<const Eigen::Vector3d> tx(x);
  Eigen::Map<const Eigen::Quaterniond> qx(x + 3);
  Eigen::Map<Eigen::Vector3d> rho(y_minus_x);
  Eigen::Map<Eigen::Vector3d> phi(y_minus_x + 3);
  rho = qx.conjugate() * (ty - tx);
  phi = QuaternionLog<double>(qx.conjugate() * qy);
  return true;
}

bool SE3Manifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> j(jacobian);
  const Eigen::Quaterniond q(Eigen::Map<const Eigen::Quaterniond>(x + 3));
  j.setZero();
  j.block<3, 3>(0, 0) = q.toRotationMatrix().transpose();
  // d(2 vec(q^-1 (x) q_y))/dq_y at q_y = q.
  const Eigen::Vector3d v = q.vec();
  j.block<3, 3>(3, 3) =
      2.0 * (q.w() * Eigen::Matrix3d::Identity() - Skew<double>(v));
  j.block<3, 1>(3, 6) = -2.0 * v;
  return true;
}

}  // namespace slam
