#include "factors/marginalization_prior.h"

#include <memory>

#include "core/manifolds.h"

namespace slam {
namespace {

using RowMajorMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

const ceres::Manifold* KindManifold(NodeKind kind) {
  static const SE2Manifold* se2 = new SE2Manifold;
  static const SE3Manifold* se3 = new SE3Manifold;
  switch (kind) {
    case NodeKind::kPose2:
      return se2;
    case NodeKind::kPose3:
      return se3;
    default:
      return nullptr;
  }
}

}  // namespace

MarginalizationPriorCost::MarginalizationPriorCost(const LinearPrior& prior)
    : prior_(prior) {
  set_num_residuals(static_cast<int>(prior_.j0.rows()));
  int offset = 0;
  for (size_t k = 0; k < prior_.keys.size(); ++k) {
    manifolds_.push_back(KindManifold(prior_.keys[k].kind));
    mutable_parameter_block_sizes()->push_back(
        static_cast<int32_t>(prior_.x0[k].size()));
    offsets_.push_back(offset);
    offset += prior_.tangent_sizes[k];
  }
}

bool MarginalizationPriorCost::Evaluate(double const* const* parameters,
                                        double* residuals,
                                        double** jacobians) const {
  const int rows = num_residuals();
  Eigen::VectorXd delta(prior_.j0.cols());
  for (size_t k = 0; k < prior_.keys.size(); ++k) {
    const int t = prior_.tangent_sizes[k];
    const double* x0 = prior_.x0[k].data();
    if (manifolds_[k] == nullptr) {
      for (int i = 0; i < t; ++i) {
        delta[offsets_[k] + i] = parameters[k][i] - x0[i];
      }
    } else if (!manifolds_[k]->Minus(parameters[k], x0,
                                     delta.data() + offsets_[k])) {
      return false;
    }
  }
  Eigen::Map<Eigen::VectorXd> r(residuals, rows);
  r = prior_.j0 * delta + prior_.r0;
  if (jacobians == nullptr) return true;
  for (size_t k = 0; k < prior_.keys.size(); ++k) {
    if (jacobians[k] == nullptr) continue;
    const int t = prior_.tangent_sizes[k];
    const int ambient = static_cast<int>(prior_.x0[k].size());
    Eigen::Map<RowMajorMatrix> jac(jacobians[k], rows, ambient);
    const auto j0_k = prior_.j0.middleCols(offsets_[k], t);
    const ceres::Manifold* manifold = manifolds_[k];
    if (manifold == nullptr) {
      jac = j0_k;
      continue;
    }
    // D = d(x [+] d [-] x0)/dd at d = 0, central differences.
    constexpr double kStep = 1e-6;
    Eigen::MatrixXd d(t, t);
    std::vector<double> moved(ambient);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(t);
    Eigen::VectorXd plus(t), minus(t);
    for (int c = 0; c < t; ++c) {
      step.setZero();
      step[c] = kStep;
      if (!manifold->Plus(parameters[k], step.data(), moved.data()) ||
          !manifold->Minus(moved.data(), prior_.x0[k].data(), plus.data())) {
        return false;
      }
      step[c] = -kStep;
      if (!manifold->Plus(parameters[k], step.data(), moved.data()) ||
          !manifold->Minus(moved.data(), prior_.x0[k].data(), minus.data())) {
        return false;
      }
      d.col(c) = (plus - minus) / (2.0 * kStep);
    }
    RowMajorMatrix minus_jacobian(t, ambient);
    if (!manifold->MinusJacobian(parameters[k], minus_jacobian.data())) {
      return false;
    }
    jac = j0_k * d * minus_jacobian;
  }
  return true;
}

bool MakeMarginalizationPrior(const LinearPrior& prior, Factor* factor,
                              std::string* error) {
  if (prior.keys.empty() || prior.j0.rows() == 0) {
    *error = "marginalization prior: no rows or no states";
    return false;
  }
  int cols = 0;
  for (int t : prior.tangent_sizes) cols += t;
  if (prior.j0.cols() != cols || prior.r0.size() != prior.j0.rows() ||
      prior.x0.size() != prior.keys.size()) {
    *error = "marginalization prior: inconsistent sizes";
    return false;
  }
  *factor = Factor();
  factor->type = FactorType::kMarginalizationPrior;
  factor->keys = prior.keys;
  factor->measurement = prior.r0;
  factor->information = prior.j0.transpose() * prior.j0;
  factor->cost = std::make_shared<MarginalizationPriorCost>(prior);
  return true;
}

}  // namespace slam
