#include "apps/marginals_report.h"

#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/marginals.h"

namespace slam {

bool ParseMarginalIds(const std::string& text, std::vector<int64_t>* ids,
                      std::string* error) {
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const long long id = std::strtoll(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0') {
      *error = "--marginals: '" + item + "' is not a node id";
      return false;
    }
    ids->push_back(id);
  }
  return true;
}

bool MarginalKeysOf(const Graph& graph, const std::vector<int64_t>& ids,
                    const std::string& input, std::vector<Key>* keys,
                    std::string* error) {
  for (int64_t id : ids) {
    const Key key2 = Pose2Key(id), key3 = Pose3Key(id);
    if (!graph.HasNode(key2) && !graph.HasNode(key3)) {
      *error = "--marginals: no node with id " + std::to_string(id) +
               " among the pose nodes of " + input;
      return false;
    }
    keys->push_back(graph.HasNode(key2) ? key2 : key3);
  }
  return true;
}

bool ReportMarginals(Graph* graph, const std::vector<Key>& keys,
                     JsonObject* json, std::string* error) {
  if (keys.empty()) return true;
  std::map<Key, Eigen::MatrixXd> covariances;
  if (!ComputeMarginals(graph, keys, &covariances, error)) {
    *error = "marginals: " + *error;
    return false;
  }
  std::printf(
      "marginal covariances (body frame, translation first, full angle):\n");
  for (const auto& [key, cov] : covariances) {
    std::printf("  node %lld:\n", static_cast<long long>(key.id));
    std::vector<double> flat;
    for (int r = 0; r < cov.rows(); ++r) {
      std::printf("   ");
      for (int c = 0; c < cov.cols(); ++c) {
        std::printf(" % .6e", cov(r, c));
        flat.push_back(cov(r, c));
      }
      std::printf("\n");
    }
    json->Add(std::to_string(key.id), flat);
  }
  return true;
}

}  // namespace slam
