// Ceres manifolds for the pose nodes. Conventions (core/conventions.h): right
// (body-frame) perturbation, translation first, full-angle rotation.
//
//   SE2Manifold: x = (x, y, theta), delta = (dx, dy, dtheta),
//     x [+] delta = (t + R(theta) (dx, dy), wrap(theta + dtheta)).
//   SE3Manifold: x = (tx, ty, tz, qx, qy, qz, qw), delta = (rho, phi),
//     x [+] delta = (t + R(q) rho, q * Exp(phi)).
//
// Minus is the exact inverse of Plus: Minus(Plus(x, d), x) = d for |d| small
// enough that the rotation stays within pi.
#ifndef SLAM_CORE_MANIFOLDS_H_
#define SLAM_CORE_MANIFOLDS_H_

#include "ceres/manifold.h"

namespace slam {

class SE2Manifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

class SE3Manifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace slam

#endif  // SLAM_CORE_MANIFOLDS_H_
