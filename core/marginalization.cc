#include "core/marginalization.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace slam {
namespace {

using RowMajorMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Ceres' corrector (internal/ceres/corrector.cc, Triggs et al. "Bundle
// adjustment - a modern synthesis", section 4.3): rescales r and J so that
// the Gauss-Newton model of 1/2 rho(|r|^2) is 1/2 |r' + J' delta|^2.
void ApplyCorrector(const ceres::LossFunction& loss, Eigen::VectorXd* r,
                    Eigen::MatrixXd* j) {
  const double sq_norm = r->squaredNorm();
  double rho[3];
  loss.Evaluate(sq_norm, rho);
  const double sqrt_rho1 = std::sqrt(rho[1]);
  double residual_scaling = sqrt_rho1;
  double alpha_sq_norm = 0.0;
  if (sq_norm > 0.0 && rho[2] > 0.0) {
    const double d = 1.0 + 2.0 * sq_norm * rho[2] / rho[1];
    const double alpha = 1.0 - std::sqrt(d);
    residual_scaling = sqrt_rho1 / (1.0 - alpha);
    alpha_sq_norm = alpha / sq_norm;
  }
  if (alpha_sq_norm != 0.0) {
    *j = sqrt_rho1 * (*j - alpha_sq_norm * (*r) * (r->transpose() * (*j)));
  } else {
    *j *= sqrt_rho1;
  }
  *r *= residual_scaling;
}

// Eigen-decomposition of a symmetric matrix with small eigenvalues (<=
// threshold * largest, or <= 0) set to zero.
void SymmetricEigen(const Eigen::MatrixXd& a, double rank_threshold,
                    Eigen::VectorXd* values, Eigen::MatrixXd* vectors) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(0.5 *
                                                        (a + a.transpose()));
  *values = solver.eigenvalues();
  *vectors = solver.eigenvectors();
  const double largest = values->size() > 0 ? values->maxCoeff() : 0.0;
  const double cut = std::max(largest, 0.0) * rank_threshold;
  for (int i = 0; i < values->size(); ++i) {
    if (!((*values)[i] > cut) || !((*values)[i] > 0.0)) (*values)[i] = 0.0;
  }
}

}  // namespace

int NodeTangentSize(const Node& node) {
  const int n = TangentSize(node.key.kind);
  return n > 0 ? n : static_cast<int>(node.value.size());
}

bool ComputeMarginalizationPrior(
    const Graph& graph, const std::vector<Key>& marginalized,
    const MarginalizationOptions& options, LinearPrior* prior,
    std::vector<FactorId>* used_factors, std::string* error,
    const LinearizationPoints* linearization_points) {
  // The value a node is linearised at: its FEJ point, else its current value.
  const auto lin_value = [&](const Node& node) -> const std::vector<double>& {
    if (linearization_points != nullptr) {
      auto it = linearization_points->find(node.key);
      if (it != linearization_points->end() &&
          it->second.size() == node.value.size()) {
        return it->second;
      }
    }
    return node.value;
  };
  *prior = LinearPrior();
  used_factors->clear();
  const std::set<Key> marg(marginalized.begin(), marginalized.end());
  for (const Key& key : marg) {
    if (!graph.HasNode(key)) {
      *error = "cannot marginalise " + key.ToString() + ": no such node";
      return false;
    }
  }
  // The factors touching M, and the kept nodes they reach.
  std::set<Key> kept;
  for (const auto& [id, factor] : graph.factors()) {
    bool touches = false;
    for (const Key& k : factor.keys) touches = touches || marg.count(k) > 0;
    if (!touches) continue;
    used_factors->push_back(id);
    for (const Key& k : factor.keys) {
      if (marg.count(k) == 0) kept.insert(k);
    }
  }
  // Tangent offsets: free marginalised nodes first, then kept nodes.
  std::map<Key, int> offset;
  int m_size = 0;
  for (const Key& key : marg) {
    const Node* node = graph.FindNode(key);
    if (node->fixed) continue;
    offset[key] = m_size;
    m_size += NodeTangentSize(*node);
  }
  int k_size = 0;
  for (const Key& key : kept) {
    const Node* node = graph.FindNode(key);
    offset[key] = m_size + k_size;
    k_size += NodeTangentSize(*node);
    prior->keys.push_back(key);
    prior->x0.push_back(lin_value(*node));
    prior->tangent_sizes.push_back(NodeTangentSize(*node));
  }
  const int n = m_size + k_size;
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);

  std::vector<const double*> params;
  std::vector<RowMajorMatrix> ambient_jacobians;
  std::vector<double*> jacobian_ptrs;
  for (FactorId id : *used_factors) {
    const Factor& factor = *graph.FindFactor(id);
    const int rows = factor.cost->num_residuals();
    params = graph.ParameterBlocks(factor);
    std::vector<const double*> lin_params(params.size());
    bool shifted = false;
    for (size_t k = 0; k < factor.keys.size(); ++k) {
      const std::vector<double>& v = lin_value(*graph.FindNode(factor.keys[k]));
      lin_params[k] = v.data();
      shifted = shifted || lin_params[k] != params[k];
    }
    ambient_jacobians.resize(factor.keys.size());
    jacobian_ptrs.resize(factor.keys.size());
    for (size_t k = 0; k < factor.keys.size(); ++k) {
      ambient_jacobians[k].resize(rows,
                                  factor.cost->parameter_block_sizes()[k]);
      jacobian_ptrs[k] = ambient_jacobians[k].data();
    }
    Eigen::VectorXd r(rows);
    // Jacobians at the linearization point; the residual at the current
    // values (moved to the linearization point below).
    if (!factor.cost->Evaluate(lin_params.data(), r.data(),
                               jacobian_ptrs.data()) ||
        (shifted && !factor.cost->Evaluate(params.data(), r.data(), nullptr))) {
      *error = "cannot marginalise: the cost function of factor " +
               std::to_string(id) + " (" + FactorTypeName(factor.type) +
               ") failed to evaluate";
      return false;
    }
    // Tangent Jacobian over the columns of this factor's free blocks.
    std::vector<int> cols;
    std::vector<int> block_offset;
    int width = 0;
    for (const Key& key : factor.keys) {
      auto it = offset.find(key);
      block_offset.push_back(it == offset.end() ? -1 : width);
      const int t = NodeTangentSize(*graph.FindNode(key));
      if (it != offset.end()) {
        for (int c = 0; c < t; ++c) cols.push_back(it->second + c);
        width += t;
      }
    }
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(rows, width);
    // (x [-] x_lin) of the free blocks: moves the residual to x_lin.
    Eigen::VectorXd shift = Eigen::VectorXd::Zero(width);
    for (size_t k = 0; k < factor.keys.size(); ++k) {
      if (block_offset[k] < 0) continue;  // Fixed marginalised node.
      const Node* node = graph.FindNode(factor.keys[k]);
      const ceres::Manifold* manifold = graph.ManifoldFor(node->key.kind);
      const int t = NodeTangentSize(*node);
      if (manifold == nullptr) {
        j.middleCols(block_offset[k], t) = ambient_jacobians[k];
        if (lin_params[k] != params[k]) {
          for (int c = 0; c < t; ++c) {
            shift[block_offset[k] + c] = params[k][c] - lin_params[k][c];
          }
        }
      } else {
        RowMajorMatrix plus(manifold->AmbientSize(), manifold->TangentSize());
        manifold->PlusJacobian(lin_params[k], plus.data());
        j.middleCols(block_offset[k], t) = ambient_jacobians[k] * plus;
        if (lin_params[k] != params[k] &&
            !manifold->Minus(params[k], lin_params[k],
                             shift.data() + block_offset[k])) {
          *error = "cannot marginalise: " + node->key.ToString() +
                   " is too far from its linearization point";
          return false;
        }
      }
    }
    if (shifted) r -= j * shift;
    if (options.use_loss && factor.loss) ApplyCorrector(*factor.loss, &r, &j);
    const Eigen::MatrixXd jtj = j.transpose() * j;
    const Eigen::VectorXd jtr = j.transpose() * r;
    for (int a = 0; a < width; ++a) {
      b[cols[a]] += jtr[a];
      for (int c = 0; c < width; ++c) h(cols[a], cols[c]) += jtj(a, c);
    }
  }

  if (k_size == 0) return true;  // Nothing kept: no prior.
  Eigen::MatrixXd h_schur = h.bottomRightCorner(k_size, k_size);
  Eigen::VectorXd b_schur = b.tail(k_size);
  if (m_size > 0) {
    Eigen::VectorXd values;
    Eigen::MatrixXd vectors;
    SymmetricEigen(h.topLeftCorner(m_size, m_size), options.rank_threshold,
                   &values, &vectors);
    Eigen::VectorXd inv = Eigen::VectorXd::Zero(values.size());
    for (int i = 0; i < values.size(); ++i) {
      if (values[i] > 0.0) inv[i] = 1.0 / values[i];
    }
    const Eigen::MatrixXd h_mm_pinv =
        vectors * inv.asDiagonal() * vectors.transpose();
    const Eigen::MatrixXd h_km_pinv =
        h.bottomLeftCorner(k_size, m_size) * h_mm_pinv;
    h_schur -= h_km_pinv * h.topRightCorner(m_size, k_size);
    b_schur -= h_km_pinv * b.head(m_size);
  }
  h_schur = 0.5 * (h_schur + h_schur.transpose());
  prior->hessian = h_schur;
  prior->gradient = b_schur;
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  SymmetricEigen(h_schur, options.rank_threshold, &values, &vectors);
  int rank = 0;
  for (int i = 0; i < values.size(); ++i) rank += values[i] > 0.0 ? 1 : 0;
  prior->j0.resize(rank, k_size);
  prior->r0.resize(rank);
  int row = 0;
  for (int i = 0; i < values.size(); ++i) {
    if (!(values[i] > 0.0)) continue;
    const double s = std::sqrt(values[i]);
    prior->j0.row(row) = s * vectors.col(i).transpose();
    prior->r0[row] = vectors.col(i).dot(b_schur) / s;
    ++row;
  }
  return true;
}

bool MarginalizeNodes(Graph* graph, const std::vector<Key>& marginalized,
                      const MarginalizationOptions& options,
                      const PriorFactorBuilder& builder, FactorId* prior_id,
                      std::string* error,
                      const LinearizationPoints* linearization_points) {
  if (prior_id != nullptr) *prior_id = -1;
  LinearPrior prior;
  std::vector<FactorId> used;
  if (!ComputeMarginalizationPrior(*graph, marginalized, options, &prior, &used,
                                   error, linearization_points)) {
    return false;
  }
  Factor factor;
  const bool add = !prior.keys.empty() && prior.j0.rows() > 0;
  if (add) {
    if (!builder) {
      *error = "cannot marginalise: no prior factor builder given";
      return false;
    }
    if (!builder(prior, &factor, error)) return false;
    factor.type = FactorType::kMarginalizationPrior;
  }
  for (FactorId id : used) graph->RemoveFactor(id);
  for (const Key& key : marginalized) graph->RemoveNode(key);
  if (add) {
    const FactorId id = graph->AddFactor(std::move(factor));
    if (id < 0) {
      *error = "cannot marginalise: the prior factor does not fit the graph";
      return false;
    }
    if (prior_id != nullptr) *prior_id = id;
  }
  return true;
}

}  // namespace slam
