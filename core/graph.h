// The factor graph: nodes (typed keys -> parameter vectors) and factors (Ceres
// cost functions over the nodes, with their measurement and information kept
// for initialization, reporting and writing back to files).
//
// Nodes live behind std::unique_ptr and their value vectors are never
// resized, so the addresses Ceres uses as parameter-block identities stay
// valid while nodes and factors are added or removed.
#ifndef SLAM_CORE_GRAPH_H_
#define SLAM_CORE_GRAPH_H_

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "ceres/cost_function.h"
#include "ceres/loss_function.h"
#include "ceres/manifold.h"
#include "ceres/problem.h"
#include "core/conventions.h"
#include "core/keys.h"
#include "core/lie.h"

namespace slam {

struct Node {
  Key key;
  // AmbientSize(key.kind) doubles. Its buffer is the Ceres parameter block:
  // never resize it or assign a temporary to it (a move would swap the
  // buffer); write values in place (std::copy, element access).
  std::vector<double> value;
  bool fixed = false;  // Held constant by the optimizer.
  TimeNs stamp = 0;    // Only meaningful when has_stamp.
  bool has_stamp = false;
};

// The semantic kind of a factor. The graph uses it for bookkeeping (counts by
// type, initialization from relative measurements, writing back to files);
// the cost itself is the CostFunction.
enum class FactorType : uint8_t {
  kBetweenSE2 = 0,  // keys {i, j}; measurement (x, y, theta) of X_i^-1 X_j.
  kBetweenSE3,      // keys {i, j}; measurement (t, q xyzw) of X_i^-1 X_j.
  kPriorSE2,        // keys {i}; measurement (x, y, theta) of X_i.
  kPriorSE3,        // keys {i}; measurement (t, q xyzw) of X_i.
  // Landmark and camera factors (factors/landmark_factors.h gives the
  // measurement layouts): keys {pose, point}.
  kRangeBearing2,   // SE(2) pose, 2D point: (range, bearing).
  kRelativePoint2,  // SE(2) pose, 2D point: point in the robot frame.
  kRelativePoint3,  // SE(3) pose, 3D point: point in the sensor frame.
  kStereo,          // SE(3) camera, 3D point: rectified stereo (uL, uR, v).
  kReprojection,    // SE(3) camera, 3D point: pinhole (u, v).
  // Inertial factors (factors/inertial_factors.h documents measurements).
  kImu,             // keys {pose_i, vel_i, bias_i, pose_j, vel_j}.
  kBiasRandomWalk,  // keys {bias_i, bias_j}.
  kPosition,        // keys {pose}; measurement (z world (3), lever arm (3)).
  kPriorVelocity,   // keys {vel}; measurement (vx, vy, vz).
  kPriorBias,       // keys {bias}; measurement (bg, ba).
  kMarginalizationPrior,  // Dense linear prior left by marginalization
                          // (core/marginalization.h); counts as a prior on
                          // every key it touches for the gauge.
  kOther,
};
const char* FactorTypeName(FactorType type);

using FactorId = int64_t;

struct Factor {
  FactorType type = FactorType::kOther;
  std::vector<Key> keys;
  // Measurement in node storage form, and information over the error vector
  // in the factor's documented residual order (see the factor's header).
  Eigen::VectorXd measurement;
  Eigen::MatrixXd information;
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;  // nullptr: plain least squares.
};

class Graph {
 public:
  Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;
  Graph(Graph&&) = default;
  Graph& operator=(Graph&&) = default;

  // Adds a node; returns nullptr if the key exists or the size is wrong.
  Node* AddNode(const Key& key, const std::vector<double>& value);
  bool HasNode(const Key& key) const { return nodes_.count(key) > 0; }
  Node* FindNode(const Key& key);
  const Node* FindNode(const Key& key) const;
  // Removes the node and every factor touching it; false if absent. Costs
  // the factors of the node and of their other nodes (the factors are
  // indexed by node), not a scan of the graph.
  bool RemoveNode(const Key& key);
  // Removes the nodes present among `keys` and every factor touching them;
  // returns how many nodes were removed. Costs the factors touching the
  // removed nodes and their neighbours, however large the graph.
  size_t RemoveNodes(const std::vector<Key>& keys);
  // The factors touching `key`, in the order they were added (empty if
  // none or absent).
  const std::vector<FactorId>& FactorsOf(const Key& key) const;
  void SetFixed(const Key& key, bool fixed);

  // Adds a factor. Every key must name an existing node and the cost function
  // parameter block sizes must match the nodes; returns -1 otherwise.
  FactorId AddFactor(Factor factor);
  bool RemoveFactor(FactorId id);
  // Sets the robust kernel of a factor (nullptr: none); false if absent.
  bool SetLoss(FactorId id, std::shared_ptr<ceres::LossFunction> loss);
  const Factor* FindFactor(FactorId id) const;

  const std::map<Key, std::unique_ptr<Node>>& nodes() const { return nodes_; }
  const std::map<FactorId, Factor>& factors() const { return factors_; }
  size_t NumNodes() const { return nodes_.size(); }
  size_t NumFactors() const { return factors_.size(); }
  bool HasFixedNode() const;

  // The gauge rule shared by the optimizers and the marginals: every
  // connected component (through the factors) that holds neither a fixed
  // node nor a prior factor gets its first node (lowest key) held constant.
  // Returns those nodes; nodes no factor touches are left out.
  std::vector<Key> GaugeAnchors() const;

  // The manifold used for nodes of this kind (nullptr: Euclidean).
  const ceres::Manifold* ManifoldFor(NodeKind kind) const;

  // Adds every node and factor to `problem`, which must have been created
  // with DO_NOT_TAKE_OWNERSHIP for cost, loss and manifold objects (see
  // ProblemOptions()). Fixed nodes are set constant. With use_loss false the
  // robust kernels are left out (plain least squares).
  void BuildProblem(ceres::Problem* problem, bool use_loss = true) const;
  static ceres::Problem::Options ProblemOptions();

  // Parameter pointers of a factor, in key order.
  std::vector<double*> ParameterBlocks(const Factor& factor);
  std::vector<const double*> ParameterBlocks(const Factor& factor) const;

  // Squared whitened error |r|^2 = e^T Omega e of one factor at the current
  // values (no robust kernel); false if the cost function fails.
  bool FactorChi2(const Factor& factor, double* chi2) const;
  // g2o-convention chi2: sum over factors of e^T Omega e (no 1/2, no kernel).
  double Chi2() const;
  // sum over factors of rho(e^T Omega e): what a robust optimizer minimizes,
  // in the same (no 1/2) scale.
  double RobustChi2() const;
  // Both in one pass over the factors.
  void Chi2AndRobustChi2(double* chi2, double* robust_chi2) const;

 private:
  std::map<Key, std::unique_ptr<Node>> nodes_;
  std::map<FactorId, Factor> factors_;
  // Node -> the factors touching it (each once, in id order), kept with
  // factors_ so that removing a node does not scan every factor.
  std::unordered_map<Key, std::vector<FactorId>, KeyHash> factors_of_;
  FactorId next_factor_id_ = 0;
  std::unique_ptr<ceres::Manifold> se2_manifold_;
  std::unique_ptr<ceres::Manifold> se3_manifold_;
};

// Measurement of a between/prior factor as a pose (types kBetweenSE2/SE3,
// kPriorSE2/SE3).
Pose2 MeasurementPose2(const Factor& factor);
Pose3 MeasurementPose3(const Factor& factor);

// Node values <-> poses.
Pose2 NodePose2(const Node& node);
Pose3 NodePose3(const Node& node);
std::vector<double> Pose2Value(const Pose2& pose);
std::vector<double> Pose3Value(const Pose3& pose);

}  // namespace slam

#endif  // SLAM_CORE_GRAPH_H_
