// Robust kernels as ceres::LossFunction, selectable by name.
//
// Ceres applies a loss to s = |r|^2 = e^T Omega e (the factor's chi2), and
// every kernel here satisfies rho(s) ~ s for small s.
//   none            rho(s) = s
//   huber:a         Ceres' HuberLoss(a), a in whitened-residual units
//   cauchy:a        Ceres' CauchyLoss(a)
//   geman_mcclure:a rho(s) = a^2 s / (a^2 + s)
//   dcs:phi         Dynamic Covariance Scaling (Agarwal et al., ICRA 2013),
//                   phi in chi2 units as in the paper and g2o. For s <= phi,
//                   rho(s) = s; beyond, rho(s) = 3 phi - 4 phi^2 / (phi + s),
//                   the C^1 kernel whose IRLS weight rho'(s) is the DCS scale
//                   squared, min(1, 2 phi / (phi + s))^2.
#ifndef SLAM_FACTORS_ROBUST_KERNELS_H_
#define SLAM_FACTORS_ROBUST_KERNELS_H_

#include <memory>
#include <string>

#include "ceres/loss_function.h"

namespace slam {

class GemanMcClureLoss : public ceres::LossFunction {
 public:
  explicit GemanMcClureLoss(double a) : a2_(a * a) {}
  void Evaluate(double s, double rho[3]) const override;

 private:
  double a2_;
};

class DcsLoss : public ceres::LossFunction {
 public:
  explicit DcsLoss(double phi) : phi_(phi) {}
  void Evaluate(double s, double rho[3]) const override;

 private:
  double phi_;
};

struct RobustKernelSpec {
  std::string kind = "none";  // none, huber, cauchy, geman_mcclure, dcs.
  double width = 1.0;
  std::string ToString() const;
};

// Parses "none", "huber:1.5", "dcs:1" ...; a kind without width uses 1.
// Returns false and sets *error on an unknown kind or a bad width.
bool ParseRobustKernel(const std::string& text, RobustKernelSpec* spec,
                       std::string* error);

// nullptr for "none".
std::shared_ptr<ceres::LossFunction> MakeLoss(const RobustKernelSpec& spec);

}  // namespace slam

#endif  // SLAM_FACTORS_ROBUST_KERNELS_H_
