// slam info FILE: what a graph file holds, before any optimization.
#include <cstdio>
#include <iostream>
#include <map>
#include <numeric>
#include <vector>

#include "apps/commands.h"
#include "core/graph.h"
#include "datasets/g2o_io.h"

DECLARE_bool(repair_information);
DECLARE_bool(skip_unknown_tags);

namespace slam {
namespace {

// Connected components of the node set through the factors (union-find).
int CountComponents(const Graph& graph, int* largest) {
  std::map<Key, int> index;
  for (const auto& [key, node] : graph.nodes()) {
    const int n = static_cast<int>(index.size());
    index[key] = n;
  }
  std::vector<int> parent(index.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [id, f] : graph.factors()) {
    for (size_t k = 1; k < f.keys.size(); ++k) {
      parent[find(index[f.keys[k]])] = find(index[f.keys[0]]);
    }
  }
  std::map<int, int> sizes;
  for (size_t i = 0; i < parent.size(); ++i) ++sizes[find(static_cast<int>(i))];
  *largest = 0;
  for (const auto& [root, size] : sizes) *largest = std::max(*largest, size);
  return static_cast<int>(sizes.size());
}

}  // namespace

int RunInfoCommand(const std::vector<std::string>& args) {
  if (args.size() != 1) {
    std::cerr << "usage: slam info FILE\n";
    return 2;
  }
  Graph graph;
  GraphReadOptions options;
  options.repair_information = FLAGS_repair_information;
  options.skip_unknown_tags = FLAGS_skip_unknown_tags;
  GraphReadReport report;
  std::string error;
  if (!ReadPoseGraph(args[0], options, &graph, &report, &error)) {
    std::cerr << "slam info: " << error << "\n";
    return 1;
  }
  for (const std::string& warning : report.warnings) {
    std::cerr << "warning: " << warning << "\n";
  }
  std::printf("file: %s\n", args[0].c_str());
  std::map<std::string, int> node_counts;
  int fixed = 0;
  for (const auto& [key, node] : graph.nodes()) {
    ++node_counts[NodeKindName(key.kind)];
    fixed += node->fixed ? 1 : 0;
  }
  std::printf("nodes: %zu", graph.NumNodes());
  for (const auto& [name, count] : node_counts) {
    std::printf("  %s %d", name.c_str(), count);
  }
  std::printf("  (fixed %d%s)\n", fixed,
              report.initialized_from_edges
                  ? "; some had no VERTEX line: initial guess from the edges"
                  : "");
  std::map<std::string, std::pair<int, double>> by_type;
  int odometry = 0, loop_closures = 0;
  for (const auto& [id, f] : graph.factors()) {
    double chi2 = 0.0;
    graph.FactorChi2(f, &chi2);
    auto& entry = by_type[FactorTypeName(f.type)];
    ++entry.first;
    entry.second += chi2;
    // Relative-pose factors only (landmark factors join a pose and a point).
    if (f.keys.size() == 2 && f.keys[0].kind == f.keys[1].kind) {
      const int64_t gap = f.keys[1].id - f.keys[0].id;
      (gap == 1 || gap == -1 ? odometry : loop_closures) += 1;
    }
  }
  std::printf("factors: %zu (odometry %d, loop closures %d)\n",
              graph.NumFactors(), odometry, loop_closures);
  for (const auto& [name, entry] : by_type) {
    std::printf("  %-14s %7d  chi2 %.10g\n", name.c_str(), entry.first,
                entry.second);
  }
  int largest = 0;
  const int components = CountComponents(graph, &largest);
  std::printf("connected components: %d (largest %d nodes)\n", components,
              largest);
  std::printf("initial chi2 (g2o convention): %.10g\n", graph.Chi2());
  if (report.repaired_information > 0) {
    std::printf("repaired information matrices: %d\n",
                report.repaired_information);
  }
  return 0;
}

}  // namespace slam
