// Dense linear prior left by marginalization (core/marginalization.h).
//
// Parameter blocks: the kept nodes x_1..x_n of the prior, any number, each in
// its node kind's storage form (SE(2) 3, SE(3) 7, Euclidean kinds their size).
// Residual (rank of the prior rows):
//   r = J0 (x [-] x0) + r0,   x [-] x0 = (Minus_1(x_1, x0_1), ...),
// where Minus_k is the node kind's manifold Minus (core/manifolds.h: right
// perturbation, translation first; Euclidean: x - x0), x0 the linearization
// point, J0 and r0 from the Schur complement. The residual is already
// whitened (J0^T J0 is the marginal information).
//
// First-estimate Jacobians: J0 and x0 are fixed for the lifetime of the
// prior. The Jacobian returned is the exact derivative of r: with respect to
// the tangent perturbation of x_k it is J0_k D_k(x_k), D_k = d(x_k [+] d [-]
// x0_k)/dd at d = 0, which is the identity at x_k = x0_k (and exactly the
// identity for Euclidean blocks). For manifold blocks D_k is computed by
// central differences on the manifold (step 1e-6, error ~1e-10), and the
// ambient Jacobian handed to Ceres is J0_k D_k MinusJacobian(x_k), whose
// product with PlusJacobian(x_k) is J0_k D_k.
#ifndef SLAM_FACTORS_MARGINALIZATION_PRIOR_H_
#define SLAM_FACTORS_MARGINALIZATION_PRIOR_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ceres/cost_function.h"
#include "ceres/manifold.h"
#include "core/graph.h"
#include "core/marginalization.h"

namespace slam {

class MarginalizationPriorCost : public ceres::CostFunction {
 public:
  // The manifolds are the node kinds' (nullptr: Euclidean); this object
  // keeps its own instances.
  explicit MarginalizationPriorCost(const LinearPrior& prior);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const LinearPrior& prior() const { return prior_; }

  static ceres::CostFunction* Create(const LinearPrior& prior) {
    return new MarginalizationPriorCost(prior);
  }

 private:
  LinearPrior prior_;
  std::vector<const ceres::Manifold*> manifolds_;
  std::vector<int> offsets_;  // Tangent column offset of each block in J0.
};

// PriorFactorBuilder for MarginalizeNodes / the sliding window: a Factor of
// type kMarginalizationPrior over prior.keys (measurement: r0; information:
// J0^T J0, the marginal information over the stacked tangent).
bool MakeMarginalizationPrior(const LinearPrior& prior, Factor* factor,
                              std::string* error);

}  // namespace slam

#endif  // SLAM_FACTORS_MARGINALIZATION_PRIOR_H_
