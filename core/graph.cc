#include "core/graph.h"

#include <algorithm>
#include <limits>
#include <unordered_set>
#include <utility>

#include "core/manifolds.h"

namespace slam {

const char* FactorTypeName(FactorType type) {
  switch (type) {
    case FactorType::kBetweenSE2:
      return "between_se2";
    case FactorType::kBetweenSE3:
      return "between_se3";
    case FactorType::kPriorSE2:
      return "prior_se2";
    case FactorType::kPriorSE3:
      return "prior_se3";
    case FactorType::kRangeBearing2:
      return "range_bearing_2d";
    case FactorType::kRelativePoint2:
      return "relative_point2";
    case FactorType::kRelativePoint3:
      return "relative_point3";
    case FactorType::kStereo:
      return "stereo";
    case FactorType::kReprojection:
      return "reprojection";
    case FactorType::kImu:
      return "imu";
    case FactorType::kBiasRandomWalk:
      return "bias_random_walk";
    case FactorType::kPosition:
      return "position";
    case FactorType::kPriorVelocity:
      return "prior_velocity";
    case FactorType::kPriorBias:
      return "prior_bias";
    case FactorType::kMarginalizationPrior:
      return "marginalization_prior";
    case FactorType::kOther:
      return "other";
  }
  return "other";
}

Graph::Graph()
    : se2_manifold_(std::make_unique<SE2Manifold>()),
      se3_manifold_(std::make_unique<SE3Manifold>()) {}

Node* Graph::AddNode(const Key& key, const std::vector<double>& value) {
  const int expected = AmbientSize(key.kind);
  if (nodes_.count(key) > 0) return nullptr;
  if (expected > 0 && static_cast<int>(value.size()) != expected) {
    return nullptr;
  }
  if (value.empty()) return nullptr;
  auto node = std::make_unique<Node>();
  node->key = key;
  node->value = value;
  Node* raw = node.get();
  nodes_.emplace(key, std::move(node));
  return raw;
}

Node* Graph::FindNode(const Key& key) {
  auto it = nodes_.find(key);
  return it == nodes_.end() ? nullptr : it->second.get();
}

const Node* Graph::FindNode(const Key& key) const {
  auto it = nodes_.find(key);
  return it == nodes_.end() ? nullptr : it->second.get();
}

bool Graph::RemoveNode(const Key& key) { return RemoveNodes({key}) == 1; }

size_t Graph::RemoveNodes(const std::vector<Key>& keys) {
  std::unordered_set<FactorId> doomed;
  std::unordered_set<Key, KeyHash> neighbours;
  size_t removed = 0;
  for (const Key& key : keys) {
    if (nodes_.erase(key) == 0) continue;
    ++removed;
    auto it = factors_of_.find(key);
    if (it == factors_of_.end()) continue;
    for (const FactorId id : it->second) {
      if (!doomed.insert(id).second) continue;
      for (const Key& k : factors_.at(id).keys) neighbours.insert(k);
    }
    factors_of_.erase(it);
  }
  for (const FactorId id : doomed) factors_.erase(id);
  // One pass over each neighbour's list (removed nodes' lists are gone).
  for (const Key& k : neighbours) {
    auto it = factors_of_.find(k);
    if (it == factors_of_.end()) continue;
    std::vector<FactorId>& ids = it->second;
    ids.erase(std::remove_if(ids.begin(), ids.end(),
                             [&](FactorId id) { return doomed.count(id) > 0; }),
              ids.end());
    if (ids.empty()) factors_of_.erase(it);
  }
  return removed;
}

const std::vector<FactorId>& Graph::FactorsOf(const Key& key) const {
  static const std::vector<FactorId> kNone;
  auto it = factors_of_.find(key);
  return it == factors_of_.end() ? kNone : it->second;
}

void Graph::SetFixed(const Key& key, bool fixed) {
  Node* node = FindNode(key);
  if (node != nullptr) node->fixed = fixed;
}

bool Graph::HasFixedNode() const {
  for (const auto& [key, node] : nodes_) {
    if (node->fixed) return true;
  }
  return false;
}

FactorId Graph::AddFactor(Factor factor) {
  if (!factor.cost) return -1;
  const std::vector<int32_t>& sizes = factor.cost->parameter_block_sizes();
  if (sizes.size() != factor.keys.size()) return -1;
  for (size_t i = 0; i < factor.keys.size(); ++i) {
    const Node* node = FindNode(factor.keys[i]);
    if (node == nullptr || static_cast<int>(node->value.size()) != sizes[i]) {
      return -1;
    }
  }
  const FactorId id = next_factor_id_++;
  for (size_t i = 0; i < factor.keys.size(); ++i) {
    // A key repeated within the factor is listed once.
    if (std::find(factor.keys.begin(), factor.keys.begin() + i,
                  factor.keys[i]) == factor.keys.begin() + i) {
      factors_of_[factor.keys[i]].push_back(id);
    }
  }
  factors_.emplace(id, std::move(factor));
  return id;
}

bool Graph::RemoveFactor(FactorId id) {
  auto it = factors_.find(id);
  if (it == factors_.end()) return false;
  for (const Key& k : it->second.keys) {
    auto list = factors_of_.find(k);
    if (list == factors_of_.end()) continue;  // Repeated key, done.
    std::vector<FactorId>& ids = list->second;
    // Ids are in increasing order.
    auto pos = std::lower_bound(ids.begin(), ids.end(), id);
    if (pos != ids.end() && *pos == id) ids.erase(pos);
    if (ids.empty()) factors_of_.erase(list);
  }
  factors_.erase(it);
  return true;
}

bool Graph::SetLoss(FactorId id, std::shared_ptr<ceres::LossFunction> loss) {
  auto it = factors_.find(id);
  if (it == factors_.end()) return false;
  it->second.loss = std::move(loss);
  return true;
}

const Factor* Graph::FindFactor(FactorId id) const {
  auto it = factors_.find(id);
  return it == factors_.end() ? nullptr : &it->second;
}

std::vector<Key> Graph::GaugeAnchors() const {
  std::map<Key, int> index;
  std::vector<const Node*> by_index;
  for (const auto& [key, node] : nodes_) {
    index[key] = static_cast<int>(by_index.size());
    by_index.push_back(node.get());
  }
  std::vector<int> parent(by_index.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<bool> touched(by_index.size(), false);
  std::vector<bool> has_prior(by_index.size(), false);
  for (const auto& [id, f] : factors_) {
    const int first = index[f.keys[0]];
    for (const Key& k : f.keys) {
      touched[index[k]] = true;
      parent[find(index[k])] = find(first);
    }
    if (f.keys.size() == 1) has_prior[first] = true;
    if (f.type == FactorType::kMarginalizationPrior) has_prior[first] = true;
  }
  // A component is anchored if any member is fixed or carries a prior.
  std::vector<bool> anchored(by_index.size(), false);
  for (size_t i = 0; i < by_index.size(); ++i) {
    if (touched[i] && (by_index[i]->fixed || has_prior[i])) {
      anchored[find(static_cast<int>(i))] = true;
    }
  }
  std::vector<Key> anchors;
  for (size_t i = 0; i < by_index.size(); ++i) {  // Key order: first wins.
    const int root = find(static_cast<int>(i));
    if (!touched[i] || anchored[root]) continue;
    anchored[root] = true;
    anchors.push_back(by_index[i]->key);
  }
  return anchors;
}

const ceres::Manifold* Graph::ManifoldFor(NodeKind kind) const {
  switch (kind) {
    case NodeKind::kPose2:
      return se2_manifold_.get();
    case NodeKind::kPose3:
      return se3_manifold_.get();
    default:
      return nullptr;
  }
}

ceres::Problem::Options Graph::ProblemOptions() {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return options;
}

std::vector<double*> Graph::ParameterBlocks(const Factor& factor) {
  std::vector<double*> blocks;
  blocks.reserve(factor.keys.size());
  for (const Key& k : factor.keys) blocks.push_back(FindNode(k)->value.data());
  return blocks;
}

std::vector<const double*> Graph::ParameterBlocks(const Factor& factor) const {
  std::vector<const double*> blocks;
  blocks.reserve(factor.keys.size());
  for (const Key& k : factor.keys) blocks.push_back(FindNode(k)->value.data());
  return blocks;
}

void Graph::BuildProblem(ceres::Problem* problem, bool use_loss) const {
  for (const auto& [key, node] : nodes_) {
    double* data = const_cast<double*>(node->value.data());
    problem->AddParameterBlock(
        data, static_cast<int>(node->value.size()),
        const_cast<ceres::Manifold*>(ManifoldFor(key.kind)));
    if (node->fixed) problem->SetParameterBlockConstant(data);
  }
  std::vector<double*> blocks;
  for (const auto& [id, factor] : factors_) {
    blocks.clear();
    for (const Key& k : factor.keys) {
      blocks.push_back(const_cast<double*>(FindNode(k)->value.data()));
    }
    problem->AddResidualBlock(factor.cost.get(),
                              use_loss ? factor.loss.get() : nullptr, blocks);
  }
}

bool Graph::FactorChi2(const Factor& factor, double* chi2) const {
  constexpr int kMaxBlocks = 8;  // No heap allocation for small factors.
  const double* stack_blocks[kMaxBlocks];
  std::vector<const double*> heap_blocks;
  const double** blocks = stack_blocks;
  if (factor.keys.size() > kMaxBlocks) {
    heap_blocks.resize(factor.keys.size());
    blocks = heap_blocks.data();
  }
  for (size_t k = 0; k < factor.keys.size(); ++k) {
    blocks[k] = FindNode(factor.keys[k])->value.data();
  }
  constexpr int kMaxResiduals = 32;  // No heap allocation for small factors.
  double stack[kMaxResiduals];
  Eigen::VectorXd heap;
  const int n = factor.cost->num_residuals();
  double* residuals = stack;
  if (n > kMaxResiduals) {
    heap.resize(n);
    residuals = heap.data();
  }
  if (!factor.cost->Evaluate(blocks, residuals, nullptr)) return false;
  *chi2 = Eigen::Map<const Eigen::VectorXd>(residuals, n).squaredNorm();
  return true;
}

double Graph::Chi2() const {
  double chi2, robust_chi2;
  Chi2AndRobustChi2(&chi2, &robust_chi2);
  return chi2;
}

double Graph::RobustChi2() const {
  double chi2, robust_chi2;
  Chi2AndRobustChi2(&chi2, &robust_chi2);
  return robust_chi2;
}

void Graph::Chi2AndRobustChi2(double* chi2, double* robust_chi2) const {
  double sum = 0.0, robust_sum = 0.0;
  for (const auto& [id, factor] : factors_) {
    double c = 0.0;
    if (!FactorChi2(factor, &c)) {
      *chi2 = *robust_chi2 = std::numeric_limits<double>::infinity();
      return;
    }
    sum += c;
    if (factor.loss) {
      double rho[3];
      factor.loss->Evaluate(c, rho);
      robust_sum += rho[0];
    } else {
      robust_sum += c;
    }
  }
  *chi2 = sum;
  *robust_chi2 = robust_sum;
}

Pose2 MeasurementPose2(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  return Pose2(m[0], m[1], m[2]);
}

Pose3 MeasurementPose3(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  return Pose3(m.head<3>(), Eigen::Quaterniond(m[6], m[3], m[4], m[5]));
}

Pose2 NodePose2(const Node& node) {
  return Pose2(node.value[0], node.value[1], node.value[2]);
}

Pose3 NodePose3(const Node& node) {
  const std::vector<double>& v = node.value;
  return Pose3(Eigen::Vector3d(v[0], v[1], v[2]),
               Eigen::Quaterniond(v[6], v[3], v[4], v[5]));
}

std::vector<double> Pose2Value(const Pose2& pose) {
  return {pose.t.x(), pose.t.y(), pose.theta};
}

std::vector<double> Pose3Value(const Pose3& pose) {
  return {pose.t.x(), pose.t.y(), pose.t.z(), pose.q.x(),
          pose.q.y(), pose.q.z(), pose.q.w()};
}

}  // namespace slam
