#include "frontends/posegraph/graph_solve.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "factors/landmark_init.h"

namespace slam {
namespace {

// Values of all nodes, to restore a start that turned out worse.
std::vector<std::vector<double>> SaveValues(const Graph& graph) {
  std::vector<std::vector<double>> values;
  for (const auto& [key, node] : graph.nodes()) values.push_back(node->value);
  return values;
}

void RestoreValues(const std::vector<std::vector<double>>& values,
                   Graph* graph) {
  size_t k = 0;
  for (const auto& [key, node] : graph->nodes()) {
    std::copy(values[k].begin(), values[k].end(), node->value.begin());
    ++k;
  }
}

bool HasBetweenFactors(const Graph& graph) {
  for (const auto& [id, f] : graph.factors()) {
    if (f.type == FactorType::kBetweenSE2 ||
        f.type == FactorType::kBetweenSE3) {
      return true;
    }
  }
  return false;
}

// True if the relative-pose factors join the pose nodes without a cycle.
bool IsForest(const Graph& graph) {
  std::map<Key, Key> parent;
  const auto find = [&parent](Key k) {
    for (auto it = parent.find(k); it != parent.end() && it->second != k;
         it = parent.find(k)) {
      k = it->second;
    }
    return k;
  };
  for (const auto& [id, f] : graph.factors()) {
    if (f.type != FactorType::kBetweenSE2 &&
        f.type != FactorType::kBetweenSE3) {
      continue;
    }
    const Key a = find(f.keys[0]);
    const Key b = find(f.keys[1]);
    if (a == b) return false;
    parent[a] = b;
    parent[f.keys[0]] = b;  // Keeps the paths short.
    parent[f.keys[1]] = b;
  }
  return true;
}

// Poses by the method, then (landmarks_from_observations) the landmarks
// again from their observations, since the poses moved.
bool InitializeWith(InitMethod method, bool landmarks_from_observations,
                    const InitOptions& options, Graph* graph,
                    std::string* error) {
  InitReport report;
  const bool ok =
      InitializePoses(graph, method, error, nullptr, options, &report);
  if (report.backend == LinearBackend::kIterative) {
    std::printf(
        "chordal initialization: no sparse factor fits, conjugate gradients "
        "(%d iterations, relative residual %.2g)\n",
        report.iterative_iterations, report.iterative_error);
  }
  if (!ok) return false;
  if (landmarks_from_observations && method != InitMethod::kNone) {
    const LandmarkInitReport report = InitializeLandmarks(graph);
    if (report.failed > 0) {
      *error = std::to_string(report.failed) +
               " landmark(s) cannot be initialized from their observations";
      return false;
    }
  }
  return true;
}

bool IsPoseKey(const Key& key) {
  return key.kind == NodeKind::kPose2 || key.kind == NodeKind::kPose3;
}

}  // namespace

InitOptions InitOptionsOf(const OptimizerOptions& optimizer) {
  InitOptions options;
  options.max_factor_bytes = optimizer.max_factor_bytes;
  options.max_factor_flops = optimizer.max_factor_flops;
  options.iterative_fallback = optimizer.iterative_fallback;
  return options;
}

bool InitializeGraph(const std::string& init, bool landmarks_from_observations,
                     const InitOptions& options, Graph* graph,
                     std::string* used, std::string* error) {
  if (!HasBetweenFactors(*graph)) {
    *used = "file (no relative-pose factors)";
    return true;
  }
  if (init != "auto") {
    InitMethod method;
    ParseInitMethod(init, &method);
    *used = init;
    return InitializeWith(method, landmarks_from_observations, options, graph,
                          error);
  }
  // Relative-pose factors forming a forest (pure odometry, as in landmark
  // SLAM files like Victoria Park) are satisfied exactly by composing them:
  // the spanning tree is the chordal solution, without the relaxation.
  const bool forest = landmarks_from_observations && IsForest(*graph);
  const InitMethod method =
      forest ? InitMethod::kSpanningTree : InitMethod::kChordal;
  const char* name = forest ? "spanning_tree" : "chordal";
  // Compared under the robust kernels when there are any: a relaxation that
  // spread outlier loop closures over the whole graph scores badly there.
  const double file_chi2 = graph->RobustChi2();
  const std::vector<std::vector<double>> file_values = SaveValues(*graph);
  if (!InitializeWith(method, landmarks_from_observations, options, graph,
                      error)) {
    return false;
  }
  const double computed_chi2 = graph->RobustChi2();
  // The better start of the two; the file's guess only when it has one.
  if (file_chi2 < computed_chi2) {
    RestoreValues(file_values, graph);
    *used = "file";
  } else {
    *used = name;
  }
  std::printf(
      "auto initialization: chi2 of the file's guess %.10g, of the "
      "%s %.10g: using %s\n",
      file_chi2,
      forest ? "spanning tree (the relative-pose factors form a tree)"
             : "chordal relaxation",
      computed_chi2, used->c_str());
  return true;
}

int OptimizeInStages(int stages, const OptimizerOptions& options,
                     Graph* graph) {
  std::vector<Key> poses;
  for (const auto& [key, node] : graph->nodes()) {
    if (IsPoseKey(key)) poses.push_back(key);
  }
  std::sort(poses.begin(), poses.end(),
            [](const Key& a, const Key& b) { return a.id < b.id; });
  OptimizerOptions quiet = options;
  quiet.verbose = false;
  int iterations = 0;
  for (int stage = stages - 1; stage >= 1; --stage) {
    const size_t count = poses.size() >> stage;
    if (count < 2) continue;
    const int64_t last_id = poses[count - 1].id;
    auto active = [&](const Key& key) {
      return !IsPoseKey(key) || key.id <= last_id;
    };
    Graph prefix;
    for (const auto& [id, factor] : graph->factors()) {
      if (!std::all_of(factor.keys.begin(), factor.keys.end(), active)) {
        continue;
      }
      for (const Key& key : factor.keys) {
        if (prefix.HasNode(key)) continue;
        const Node* node = graph->FindNode(key);
        prefix.AddNode(key, node->value);
        if (node->fixed) prefix.SetFixed(key, true);
      }
      prefix.AddFactor(factor);
    }
    const OptimizerSummary summary = Optimize(&prefix, quiet, nullptr);
    iterations += summary.iterations;
    std::printf(
        "stage %d/%d: poses up to id %lld (%zu of %zu), chi2 %.10g -> %.10g, "
        "%d iterations\n",
        stages - stage, stages, static_cast<long long>(last_id), count,
        poses.size(), summary.initial_chi2, summary.final_chi2,
        summary.iterations);
    if (!summary.usable) break;
    std::set<Key> later_poses, later_points;
    for (const auto& [key, node] : graph->nodes()) {
      if (prefix.HasNode(key)) {
        node->value = prefix.FindNode(key)->value;
      } else {
        (IsPoseKey(key) ? later_poses : later_points).insert(key);
      }
    }
    std::string error;
    if (!later_poses.empty() &&
        !InitializePoses(graph, InitMethod::kSpanningTree, &error,
                         &later_poses)) {
      std::printf("stage %d/%d: %s; the remaining poses keep their values\n",
                  stages - stage, stages, error.c_str());
    }
    if (!later_points.empty()) InitializeLandmarks(graph, &later_points);
  }
  return iterations;
}

OptimizerSummary OptimizeGraph(int stages, const OptimizerOptions& options,
                               Graph* graph, std::ostream* log) {
  int stage_iterations = 0;
  double chi2_before_stages = 0.0, robust_chi2_before_stages = 0.0;
  if (stages > 1) {
    chi2_before_stages = graph->Chi2();
    robust_chi2_before_stages = graph->RobustChi2();
    stage_iterations = OptimizeInStages(stages, options, graph);
  }
  OptimizerSummary summary = Optimize(graph, options, log);
  if (stage_iterations > 0) {
    summary.iterations += stage_iterations;
    summary.initial_chi2 = chi2_before_stages;
    summary.initial_robust_chi2 = robust_chi2_before_stages;
  }
  return summary;
}

}  // namespace slam
