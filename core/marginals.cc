#include "core/marginals.h"

#include <set>
#include <utility>

#include "ceres/covariance.h"
#include "ceres/problem.h"
#include "core/openmp_scope.h"

namespace slam {

bool ComputeMarginals(Graph* graph, const std::vector<Key>& keys,
                      std::map<Key, Eigen::MatrixXd>* covariances,
                      std::string* error) {
  for (const Key& key : keys) {
    if (!graph->HasNode(key)) {
      *error = "no node " + key.ToString() + " in the graph";
      return false;
    }
  }
  ceres::Problem problem(Graph::ProblemOptions());
  graph->BuildProblem(&problem);
  for (const Key& key : graph->GaugeAnchors()) {
    problem.SetParameterBlockConstant(graph->FindNode(key)->value.data());
  }
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = 2;
  ceres::Covariance covariance(options);
  // A free node that no factor touches is not determined at all, but Ceres
  // would report a zero covariance for it: refuse, as for rank deficiency.
  std::set<Key> constrained;
  for (const auto& [id, f] : graph->factors()) {
    constrained.insert(f.keys.begin(), f.keys.end());
  }
  std::vector<std::pair<const double*, const double*>> blocks;
  std::set<const double*> requested;  // Ceres aborts on duplicate blocks.
  for (const Key& key : keys) {
    const double* data = graph->FindNode(key)->value.data();
    if (constrained.count(key) == 0 &&
        !problem.IsParameterBlockConstant(data)) {
      *error = "the system is rank deficient: node " + key.ToString() +
               " is not constrained by any factor, so its covariance is "
               "undefined";
      return false;
    }
    if (requested.insert(data).second) blocks.emplace_back(data, data);
  }
  const SerialOpenMpScope serial_openmp;
  if (!covariance.Compute(blocks, &problem)) {
    *error =
        "the system is rank deficient: some nodes are not determined by the "
        "factors (disconnected parts, or too few constraints), so their "
        "covariance is undefined";
    return false;
  }
  for (const Key& key : keys) {
    const Node* node = graph->FindNode(key);
    const int n = TangentSize(key.kind) > 0
                      ? TangentSize(key.kind)
                      : static_cast<int>(node->value.size());
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(n,
                                                                             n);
    if (!covariance.GetCovarianceBlockInTangentSpace(
            node->value.data(), node->value.data(), c.data())) {
      *error = "could not extract the covariance of " + key.ToString();
      return false;
    }
    (*covariances)[key] = c;
  }
  return true;
}

}  // namespace slam
