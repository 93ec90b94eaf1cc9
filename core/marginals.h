// Marginal covariances of chosen nodes at the current estimate.
//
// Covariances are expressed in the node's tangent space as documented in
// core/conventions.h: body frame, translation first, full-angle rotation
// (SE(2): x, y, theta; SE(3): rho(3), phi(3)). The gauge is removed as the
// optimizer removes it (fixed nodes, else priors, else the first node held
// constant in each component; Graph::GaugeAnchors), so the covariance of a
// node is relative to that gauge.
#ifndef SLAM_CORE_MARGINALS_H_
#define SLAM_CORE_MARGINALS_H_

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/graph.h"

namespace slam {

// Returns false with a clear *error when a key is absent or the system is
// rank deficient (some direction of the state is not determined by the
// factors). Fixed (constant) nodes get a zero covariance.
bool ComputeMarginals(Graph* graph, const std::vector<Key>& keys,
                      std::map<Key, Eigen::MatrixXd>* covariances,
                      std::string* error);

// The joint covariance of `keys` (with their cross-covariances), blocks in
// the order of `keys`, each in its node's tangent space. Same conditions.
bool ComputeJointMarginal(Graph* graph, const std::vector<Key>& keys,
                          Eigen::MatrixXd* joint, std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_MARGINALS_H_
