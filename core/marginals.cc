#include "core/marginals.h"

#include <set>
#include <utility>

#include "ceres/covariance.h"
#include "ceres/problem.h"
#include "core/openmp_scope.h"

namespace slam {

namespace {

int NodeTangent(const Node& node) {
  return TangentSize(node.key.kind) > 0 ? TangentSize(node.key.kind)
                                        : static_cast<int>(node.value.size());
}

// Builds the problem with the gauge held, checks the keys and computes the
// covariance blocks (a, b) of the keys for all a <= b (`joint`) or a == b.
bool ComputeCovariance(Graph* graph, const std::vector<Key>& keys, bool joint,
                       ceres::Problem* problem, ceres::Covariance* covariance,
                       std::string* error) {
  for (const Key& key : keys) {
    if (!graph->HasNode(key)) {
      *error = "no node " + key.ToString() + " in the graph";
      return false;
    }
  }
  graph->BuildProblem(problem);
  for (const Key& key : graph->GaugeAnchors()) {
    problem->SetParameterBlockConstant(graph->FindNode(key)->value.data());
  }
  // A free node that no factor touches is not determined at all, but Ceres
  // would report a zero covariance for it: refuse, as for rank deficiency.
  std::set<Key> constrained;
  for (const auto& [id, f] : graph->factors()) {
    constrained.insert(f.keys.begin(), f.keys.end());
  }
  std::vector<const double*> unique;
  std::set<const double*> seen;  // Ceres aborts on duplicate blocks.
  for (const Key& key : keys) {
    const double* data = graph->FindNode(key)->value.data();
    if (constrained.count(key) == 0 &&
        !problem->IsParameterBlockConstant(data)) {
      *error = "the system is rank deficient: node " + key.ToString() +
               " is not constrained by any factor, so its covariance is "
               "undefined";
      return false;
    }
    if (seen.insert(data).second) unique.push_back(data);
  }
  std::vector<std::pair<const double*, const double*>> blocks;
  for (size_t a = 0; a < unique.size(); ++a) {
    for (size_t b = a; b < (joint ? unique.size() : a + 1); ++b) {
      blocks.emplace_back(unique[a], unique[b]);
    }
  }
  const SerialOpenMpScope serial_openmp;
  if (!covariance->Compute(blocks, problem)) {
    *error =
        "the system is rank deficient: some nodes are not determined by the "
        "factors (disconnected parts, or too few constraints), so their "
        "covariance is undefined";
    return false;
  }
  return true;
}

ceres::Covariance::Options CovarianceOptions() {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = 2;
  return options;
}

using RowMajorMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace

bool ComputeMarginals(Graph* graph, const std::vector<Key>& keys,
                      std::map<Key, Eigen::MatrixXd>* covariances,
                      std::string* error) {
  ceres::Problem problem(Graph::ProblemOptions());
  ceres::Covariance covariance(CovarianceOptions());
  if (!ComputeCovariance(graph, keys, false, &problem, &covariance, error)) {
    return false;
  }
  for (const Key& key : keys) {
    const Node* node = graph->FindNode(key);
    const int n = NodeTangent(*node);
    RowMajorMatrix c(n, n);
    if (!covariance.GetCovarianceBlockInTangentSpace(
            node->value.data(), node->value.data(), c.data())) {
      *error = "could not extract the covariance of " + key.ToString();
      return false;
    }
    (*covariances)[key] = c;
  }
  return true;
}

bool ComputeJointMarginal(Graph* graph, const std::vector<Key>& keys,
                          Eigen::MatrixXd* joint, std::string* error) {
  ceres::Problem problem(Graph::ProblemOptions());
  ceres::Covariance covariance(CovarianceOptions());
  if (!ComputeCovariance(graph, keys, true, &problem, &covariance, error)) {
    return false;
  }
  std::vector<int> offset;
  int size = 0;
  for (const Key& key : keys) {
    offset.push_back(size);
    size += NodeTangent(*graph->FindNode(key));
  }
  joint->setZero(size, size);
  for (size_t a = 0; a < keys.size(); ++a) {
    for (size_t b = 0; b < keys.size(); ++b) {
      const Node* na = graph->FindNode(keys[a]);
      const Node* nb = graph->FindNode(keys[b]);
      RowMajorMatrix c(NodeTangent(*na), NodeTangent(*nb));
      if (!covariance.GetCovarianceBlockInTangentSpace(
              na->value.data(), nb->value.data(), c.data())) {
        *error = "could not extract the covariance of " + keys[a].ToString() +
                 " and " + keys[b].ToString();
        return false;
      }
      joint->block(offset[a], offset[b], c.rows(), c.cols()) = c;
    }
  }
  return true;
}

}  // namespace slam
