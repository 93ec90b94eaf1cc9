// Marginalization of nodes out of a Graph by a Schur complement on the
// linearised factors that touch them.
//
// Given the keys M to marginalise, every factor touching a key of M is
// linearised at the current values:
//   r_f(x [+] delta) ~ r_f + J_f delta,
// with delta in each node's tangent space (core/conventions.h: right
// perturbation, translation first; Euclidean nodes: delta = dx). The tangent
// Jacobian is the cost function's ambient Jacobian times the manifold's
// PlusJacobian, so any factor and node kind works. Robust kernels are applied
// as Ceres applies them (its "corrector": residual and Jacobian rescaled so
// that the Gauss-Newton model of rho(|r|^2) is matched, Triggs et al.).
//
// The factors give H = sum J^T J and b = sum J^T r over the blocks
// (M, K), K being the kept nodes those factors also touch. The marginalised
// block is eliminated:
//   H* = H_KK - H_KM H_MM^+ H_MK,   b* = b_K - H_KM H_MM^+ b_M,
// where H_MM^+ is the pseudo-inverse from an eigen-decomposition that
// drops eigenvalues <= rank_threshold * (largest eigenvalue) (directions of M
// no factor determines carry no information into K). H* is then factored as
// H* = J0^T J0 with J0 = S^1/2 V^T (eigenvalues of H* below the same relative
// threshold dropped, so J0 has rank(H*) rows) and r0 = S^-1/2 V^T b*, so that
//   1/2 |J0 delta + r0|^2 = 1/2 delta^T H* delta + delta^T b* + const,
// the quadratic model of the marginalised problem over K (the constant, i.e.
// the chi2 the removed factors had at their optimum, is not kept).
//
// The prior is expressed at the linearization point x0 of K, r(x) =
// J0 (x [-] x0) + r0 (factors/marginalization_prior.h). J0 and x0 never
// change afterwards.
//
// First-estimate Jacobians (FEJ, Huang, Mourikis and Roumeliotis): a node
// that a prior already touches must keep ONE linearization point in every
// later prior, or the priors disagree about the directions the data leave
// unobserved and the window gains spurious information there. Pass the
// nodes' linearization points in `linearization_points` (the sliding window
// keeps them: a node's x0 in the first prior that touches it). Every factor
// touching M is then linearised with its Jacobians at those points (current
// values for nodes without one), and its residual is moved there from the
// current values to first order, r_lin = r(x) - J (x [-] x_lin), which keeps
// the information the current residual carries; a kept node with a point
// has it as its x0 in the new prior. Without points, everything is linearised
// at the current values (x0 = the values at marginalization time).
//
// Fixed marginalised nodes contribute no tangent columns (they are constants);
// fixed kept nodes are kept in the prior, which is harmless: the (free, free)
// block of the Schur complement is the same with or without them.
//
// core knows no concrete prior cost function (it lives in factors/); the
// caller passes a PriorFactorBuilder, normally MakeMarginalizationPrior from
// factors/marginalization_prior.h.
#ifndef SLAM_CORE_MARGINALIZATION_H_
#define SLAM_CORE_MARGINALIZATION_H_

#include <Eigen/Core>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/graph.h"

namespace slam {

struct MarginalizationOptions {
  // Relative eigenvalue threshold for the pseudo-inverse of H_MM and for the
  // rank of the prior (eigenvalues <= threshold * largest are zero).
  double rank_threshold = 1e-12;
  // Apply the factors' robust kernels (Ceres' corrector); false: plain least
  // squares.
  bool use_loss = true;
};

// A dense linear prior over kept nodes: r(x) = J0 (x [-] x0) + r0.
struct LinearPrior {
  std::vector<Key> keys;                // Kept nodes, in key order.
  std::vector<std::vector<double>> x0;  // Their values at linearization.
  std::vector<int> tangent_sizes;       // Tangent size of each key.
  Eigen::MatrixXd j0;                   // rank x sum(tangent_sizes).
  Eigen::VectorXd r0;                   // rank.
  Eigen::MatrixXd hessian;              // H* (sum tangent)^2, for reference.
  Eigen::VectorXd gradient;             // b*.
};

// Tangent size of a node (its kind's, or its value size for Euclidean
// variable-size kinds).
int NodeTangentSize(const Node& node);

// Linearises the factors touching `marginalized` at the current values and
// Schur-complements the marginalised block. Fills *prior (its keys may be
// empty when the marginalised nodes connect to nothing else) and the ids of
// the factors used. Does not modify the graph.
// Linearization points of nodes (FEJ), by key; nodes absent use their
// current values.
using LinearizationPoints = std::map<Key, std::vector<double>>;

bool ComputeMarginalizationPrior(
    const Graph& graph, const std::vector<Key>& marginalized,
    const MarginalizationOptions& options, LinearPrior* prior,
    std::vector<FactorId>* used_factors, std::string* error,
    const LinearizationPoints* linearization_points = nullptr);

// Builds the graph factor (type kMarginalizationPrior) for a prior.
using PriorFactorBuilder = std::function<bool(
    const LinearPrior& prior, Factor* factor, std::string* error)>;

// ComputeMarginalizationPrior, then removes the used factors and the
// marginalised nodes from the graph and adds the prior built by `builder`
// (none when it has no rows or no keys). *prior_id is the new factor's id or
// -1 when none was added (may be nullptr).
bool MarginalizeNodes(
    Graph* graph, const std::vector<Key>& marginalized,
    const MarginalizationOptions& options, const PriorFactorBuilder& builder,
    FactorId* prior_id, std::string* error,
    const LinearizationPoints* linearization_points = nullptr);

}  // namespace slam

#endif  // SLAM_CORE_MARGINALIZATION_H_
