// slam optimize: read a pose graph, initialize, optimize, write the result.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include <gflags/gflags.h>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/json.h"
#include "apps/map_plot.h"
#include "apps/optimize_config.h"
#include "apps/yaml_config.h"
#include "core/initialization.h"
#include "core/marginals.h"
#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/stereo_vo_io.h"
#include "datasets/trajectory_io.h"
#include "factors/landmark_factors.h"
#include "factors/landmark_init.h"

DEFINE_string(i, "",
              "input graph file (g2o, TORO .graph, iSAM; or the stereo "
              "factors file with --stereo_calibration and --stereo_poses)");
DEFINE_string(stereo_calibration, "",
              "stereo VO input: calibration file 'fx fy skew cx cy baseline' "
              "(-i is then the stereo factors file)");
DEFINE_string(stereo_poses, "",
              "stereo VO input: camera poses 'id + 4x4 row-major' "
              "(camera-to-world)");
DEFINE_string(robust_landmark, "none",
              "robust kernel on the landmark and camera factors: none, "
              "huber:W, cauchy:W, geman_mcclure:W, dcs:PHI");
DEFINE_string(o, "", "output file (optimize: graph, .g2o or .graph)");
DEFINE_bool(skip_unknown_tags, false,
            "optimize, info: skip input lines whose tag is not read (with a "
            "warning per tag, as g2o does) instead of failing");
DEFINE_string(init, "auto",
              "initial guess: auto, none, odometry, spanning_tree, chordal");
DEFINE_string(solver, "lm", "lm, gn or dogleg");
DEFINE_string(robust, "none",
              "robust kernel on all between factors: none, huber:W, cauchy:W, "
              "geman_mcclure:W, dcs:PHI");
DEFINE_int32(max_iterations, 100, "iteration limit");
DEFINE_string(marginals, "",
              "comma-separated node ids whose marginal covariance to print");
DEFINE_bool(
    repair_information, false,
    "replace information matrices that are not positive definite by "
    "the nearest positive-definite matrix (counted) instead of failing");
DEFINE_string(ordering, "auto",
              "elimination ordering: auto, amd, metis, nesdis, ceres");
DEFINE_bool(quiet, false, "no per-iteration lines");
DEFINE_bool(ceres_report, false,
            "print Ceres' full solver report (where the time goes)");

namespace slam {
namespace {

bool FlagGiven(const char* name) {
  return !gflags::GetCommandLineFlagInfoOrDie(name).is_default;
}

// defaults < --config < explicit flags.
bool BuildConfig(OptimizeConfig* config, std::string* error) {
  if (!FLAGS_config.empty() &&
      !LoadOptimizeConfig(FLAGS_config, config, error)) {
    return false;
  }
  if (FlagGiven("init")) config->init = FLAGS_init;
  if (FlagGiven("solver") &&
      !ParseSolverKind(FLAGS_solver, &config->optimizer.solver)) {
    *error = "--solver '" + FLAGS_solver + "' is not one of lm, gn, dogleg";
    return false;
  }
  if (FlagGiven("robust")) {
    RobustKernelSpec spec;
    if (!ParseRobustKernel(FLAGS_robust, &spec, error)) {
      *error = "--robust: " + *error;
      return false;
    }
    config->robust_odometry = spec;
    config->robust_loop_closure = spec;
  }
  if (FlagGiven("robust_landmark") &&
      !ParseRobustKernel(FLAGS_robust_landmark, &config->robust_landmark,
                         error)) {
    *error = "--robust_landmark: " + *error;
    return false;
  }
  if (FlagGiven("max_iterations")) {
    config->optimizer.max_iterations = FLAGS_max_iterations;
  }
  if (FlagGiven("repair_information")) {
    config->repair_information = FLAGS_repair_information;
  }
  if (FlagGiven("ordering")) config->optimizer.ordering = FLAGS_ordering;
  if (FLAGS_quiet) config->optimizer.verbose = false;
  return ValidateOptimizeConfig(*config, error);
}

bool ParseIds(const std::string& text, std::vector<int64_t>* ids,
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

// Which robust kernel a factor gets.
const RobustKernelSpec& KernelFor(const OptimizeConfig& config,
                                  const Factor& factor) {
  if (IsLandmarkFactor(factor.type)) return config.robust_landmark;
  if (factor.keys.size() == 1) return config.robust_prior;
  const int64_t gap = factor.keys[1].id - factor.keys[0].id;
  return gap == 1 || gap == -1 ? config.robust_odometry
                               : config.robust_loop_closure;
}

void ApplyKernels(const OptimizeConfig& config, Graph* graph) {
  std::vector<std::pair<FactorId, std::shared_ptr<ceres::LossFunction>>> losses;
  for (const auto& [id, factor] : graph->factors()) {
    losses.emplace_back(id, MakeLoss(KernelFor(config, factor)));
  }
  for (auto& [id, loss] : losses) graph->SetLoss(id, std::move(loss));
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
}

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
// The initialization's limits on sparse factors are the optimizer's.
InitOptions InitOptionsOf(const OptimizerOptions& optimizer) {
  InitOptions options;
  options.max_factor_bytes = optimizer.max_factor_bytes;
  options.max_factor_flops = optimizer.max_factor_flops;
  options.iterative_fallback = optimizer.iterative_fallback;
  return options;
}

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

// Landmark SLAM from dead reckoning (an odometry tree, landmarks placed at
// their first sightings): solved over growing prefixes of the trajectory
// (poses by id, which is time in these files), 1/2^(stages-1), ..., 1/2 of
// the poses, then all. After each prefix the poses beyond it are composed
// again from the optimized end of the prefix and the landmarks first seen
// beyond it are placed again from the optimized poses. Victoria Park: one
// batch solve from dead reckoning stops in a local minimum (chi2 503277,
// landmarks up to 265 m off) where every batch solver tried stays; solving
// the first half first places the landmarks of the second half well enough
// that the batch reaches the good minimum (6183.93, as incremental iSAM).
// Returns the summed iterations of the prefix solves.
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

// Runs the configured initialization; returns the name of what was used.
// Graphs without relative-pose factors (bundle adjustment) keep their poses.
bool Initialize(const std::string& init, bool landmarks_from_observations,
                const InitOptions& options, Graph* graph, std::string* used,
                std::string* error) {
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

// --gt: evaluates the optimized poses (stamped by node id, in seconds, as
// `slam simulate` stamps its ground truth) against the reference.
bool EvaluateAgainstGroundTruth(const Graph& graph, const TrajectoryData& gt,
                                JsonObject* report, std::string* error) {
  Trajectory estimate;
  if (!TrajectoryFromGraph(graph, false, &estimate, error)) return false;
  EvalSettings settings;
  if (!LoadEvalSectionOfConfig(FLAGS_config, &settings, error)) return false;
  settings.association = ChooseAssociation(gt.has_stamps, true);
  EvalLabels labels;
  labels.ref_name = "ground truth";
  labels.est_name = "optimized";
  EvalResult result;
  std::printf("\nevaluation against %s:\n", FLAGS_gt.c_str());
  if (!EvaluateAndReport(gt.poses, estimate, settings, labels, FLAGS_plot,
                         std::cout, &result, error)) {
    return false;
  }
  report->Add("evaluation", EvalResultJson(result, settings));
  return true;
}

}  // namespace

int RunOptimizeCommand(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  OptimizeConfig config;
  std::string error;
  if (!BuildConfig(&config, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 2;
  }
  if (FLAGS_dump_config) {
    std::cout << OptimizeConfigToYaml(config);
    return 0;
  }
  std::string input = FLAGS_i;
  if (input.empty() && args.size() == 1) input = args[0];
  if (args.size() > (FLAGS_i.empty() ? 1u : 0u)) {
    std::cerr << "slam optimize: unexpected argument '" << args.back()
              << "' (one input: -i IN or a single positional argument)\n";
    return 2;
  }
  if (input.empty()) {
    std::cerr << "slam optimize: no input; usage: slam optimize -i IN [-o OUT]"
                 " [--init ...] [--solver ...] [--robust KIND:WIDTH]"
                 " [--max_iterations N] [--marginals ID,...] [--config FILE]"
                 " [--report FILE.json]\n";
    return 2;
  }
  std::vector<int64_t> marginal_ids;
  if (!ParseIds(FLAGS_marginals, &marginal_ids, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 2;
  }

  // Fail before any work on outputs that cannot be written and on a ground
  // truth that cannot be read: a failed run leaves no output behind.
  for (const std::string& out : {FLAGS_o, FLAGS_report}) {
    if (out.empty()) continue;
    const std::filesystem::path parent =
        std::filesystem::absolute(out).parent_path();
    if (!std::filesystem::is_directory(parent)) {
      std::cerr << "slam optimize: " << out << ": the directory "
                << parent.string() << " does not exist\n";
      return 1;
    }
    if (std::filesystem::is_directory(out)) {
      std::cerr << "slam optimize: " << out << ": is a directory\n";
      return 1;
    }
  }
  TrajectoryData gt;
  if (!FLAGS_gt.empty() && !ReadTrajectory(FLAGS_gt, {}, &gt, &error)) {
    std::cerr << "slam optimize: --gt: " << error << "\n";
    return 1;
  }

  // Load.
  Graph graph;
  GraphReadOptions read_options;
  read_options.repair_information = config.repair_information;
  read_options.skip_unknown_tags = FLAGS_skip_unknown_tags;
  GraphReadReport read_report;
  const bool stereo_vo =
      !FLAGS_stereo_calibration.empty() || !FLAGS_stereo_poses.empty();
  if (stereo_vo) {
    if (FLAGS_stereo_calibration.empty() || FLAGS_stereo_poses.empty()) {
      std::cerr << "slam optimize: the stereo VO input needs both "
                   "--stereo_calibration and --stereo_poses\n";
      return 2;
    }
    StereoVoReport stereo_report;
    if (!ReadStereoVo(input, FLAGS_stereo_calibration, FLAGS_stereo_poses,
                      &graph, &stereo_report, &error)) {
      std::cerr << "slam optimize: " << error << "\n";
      return 1;
    }
    std::printf("stereo VO: %d camera poses, %d landmarks, %d measurements\n",
                stereo_report.poses, stereo_report.landmarks,
                stereo_report.measurements);
  } else if (!ReadPoseGraph(input, read_options, &graph, &read_report,
                            &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 1;
  }
  for (const std::string& warning : read_report.warnings) {
    std::cerr << "warning: " << warning << "\n";
  }
  if (read_report.repaired_information > 0) {
    std::cerr << "repaired " << read_report.repaired_information
              << " information matrices that were not positive definite\n";
  }
  if (graph.NumFactors() == 0) {
    std::cerr << "slam optimize: " << input
              << ": no edges (factors): nothing to optimize\n";
    return 1;
  }
  const double load_seconds = Seconds(start);
  const double file_chi2 = graph.Chi2();
  std::printf("loaded %s: %zu nodes, %zu factors, chi2 %.10g (%.3f s)\n",
              input.c_str(), graph.NumNodes(), graph.NumFactors(), file_chi2,
              load_seconds);

  // Marginal ids name pose nodes (the file's single id space).
  std::vector<Key> marginal_keys;
  for (int64_t id : marginal_ids) {
    const Key key2 = Pose2Key(id), key3 = Pose3Key(id);
    if (!graph.HasNode(key2) && !graph.HasNode(key3)) {
      std::cerr << "slam optimize: --marginals: no node with id " << id
                << " among the pose nodes of " << input << "\n";
      return 1;
    }
    marginal_keys.push_back(graph.HasNode(key2) ? key2 : key3);
  }

  ApplyKernels(config, &graph);

  // Initialize.
  const auto init_start = std::chrono::steady_clock::now();
  std::string init_used;
  size_t num_points = 0;
  for (const auto& [key, node] : graph.nodes()) {
    num_points +=
        key.kind == NodeKind::kPoint2 || key.kind == NodeKind::kPoint3;
  }
  // Landmarks the file gave no values for follow the poses.
  const bool landmarks_from_observations =
      num_points > 0 &&
      read_report.landmarks_initialized == static_cast<int>(num_points);
  if (num_points > 0) {
    std::printf("landmarks: %zu (%s)\n", num_points,
                landmarks_from_observations
                    ? "initialized from their observations"
                    : "values from the input");
  }
  const PixelErrorStats pixels_before = CameraPixelErrors(graph);
  if (!Initialize(config.init, landmarks_from_observations,
                  InitOptionsOf(config.optimizer), &graph, &init_used,
                  &error)) {
    std::cerr << "slam optimize: initialization failed: " << error << "\n";
    return 1;
  }
  const double init_seconds = Seconds(init_start);
  std::printf("initialization: %s, chi2 %.10g (%.3f s)\n", init_used.c_str(),
              graph.Chi2(), init_seconds);

  // Solve.
  int stage_iterations = 0;
  const double chi2_before_stages = graph.Chi2();
  const double robust_chi2_before_stages = graph.RobustChi2();
  if (config.init == "auto" && init_used == "spanning_tree" &&
      landmarks_from_observations && config.landmark_stages > 1) {
    stage_iterations =
        OptimizeInStages(config.landmark_stages, config.optimizer, &graph);
  }
  OptimizerSummary summary = Optimize(&graph, config.optimizer, &std::cout);
  if (stage_iterations > 0) {
    summary.iterations += stage_iterations;
    summary.initial_chi2 = chi2_before_stages;
    summary.initial_robust_chi2 = robust_chi2_before_stages;
  }
  if (!summary.usable) {
    std::cerr << "slam optimize: the solver failed: " << summary.termination
              << "\n";
    return 1;
  }
  if (FLAGS_ceres_report) std::cout << summary.full_report << "\n";
  if (!summary.linear_solver_reason.empty()) {
    std::printf("linear solver choice: %s\n",
                summary.linear_solver_reason.c_str());
  }
  const PixelErrorStats pixels_after = CameraPixelErrors(graph);
  if (pixels_before.factors > 0) {
    std::printf(
        "reprojection RMS %.6g -> %.6g px over %d camera factors (%d with the "
        "point behind the camera after)\n",
        pixels_before.rms, pixels_after.rms, pixels_after.factors,
        pixels_after.behind);
  }
  std::printf("solver: %s, linear solver %s (%s, ordering %s), gauge: %s\n",
              SolverKindName(config.optimizer.solver),
              summary.linear_solver.c_str(), summary.sparse_library.c_str(),
              summary.ordering.c_str(), summary.gauge.c_str());

  // Marginals.
  JsonObject marginals_json;
  if (!marginal_keys.empty()) {
    const std::vector<Key>& keys = marginal_keys;
    std::map<Key, Eigen::MatrixXd> covariances;
    if (!ComputeMarginals(&graph, keys, &covariances, &error)) {
      std::cerr << "slam optimize: marginals: " << error << "\n";
      return 1;
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
      marginals_json.Add(std::to_string(key.id), flat);
    }
  }

  JsonObject evaluation;
  if (!FLAGS_gt.empty() &&
      !EvaluateAgainstGroundTruth(graph, gt, &evaluation, &error)) {
    std::cerr << "slam optimize: --gt: " << error << "\n";
    return 1;
  }

  if (num_points > 0 && !FLAGS_plot.empty()) {
    const std::string path = FLAGS_plot + "/map.png";
    if (!CreateOutputFolder(FLAGS_plot, &error) ||
        !WriteMapPlot(
            path,
            MapPlotFromGraph(
                graph, "optimized map: " +
                           std::filesystem::path(input).filename().string()),
            &error)) {
      std::cerr << "slam optimize: --plot: " << error << "\n";
      return 1;
    }
    std::printf("wrote %s\n", path.c_str());
  }

  // Write.
  const auto write_start = std::chrono::steady_clock::now();
  if (!FLAGS_o.empty() && !WritePoseGraph(FLAGS_o, graph, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 1;
  }
  const double write_seconds = Seconds(write_start);
  const double total_seconds = Seconds(start);
  std::printf("chi2 %.10g -> %.10g in %d iterations (%s); total %.3f s%s%s\n",
              summary.initial_chi2, summary.final_chi2, summary.iterations,
              summary.converged ? "converged" : "NOT converged", total_seconds,
              FLAGS_o.empty() ? "" : ", wrote ", FLAGS_o.c_str());

  if (!FLAGS_report.empty()) {
    JsonObject report;
    report.Add("input", input)
        .Add("nodes", graph.NumNodes())
        .Add("factors", graph.NumFactors())
        .Add("file_chi2", file_chi2)
        .Add("initial_chi2", summary.initial_chi2)
        .Add("final_chi2", summary.final_chi2)
        .Add("initial_robust_chi2", summary.initial_robust_chi2)
        .Add("final_robust_chi2", summary.final_robust_chi2)
        .Add("iterations", summary.iterations)
        .Add("converged", summary.converged)
        .Add("termination", summary.termination)
        .Add("init", init_used)
        .Add("solver", SolverKindName(config.optimizer.solver))
        .Add("linear_solver", summary.linear_solver)
        .Add("sparse_library", summary.sparse_library)
        .Add("ordering", summary.ordering)
        .Add("repaired_information", read_report.repaired_information)
        .Add("load_seconds", load_seconds)
        .Add("init_seconds", init_seconds)
        .Add("solve_seconds", summary.solve_seconds)
        .Add("write_seconds", write_seconds)
        .Add("total_seconds", total_seconds);
    if (num_points > 0) report.Add("landmarks", num_points);
    if (pixels_before.factors > 0) {
      report.Add("reprojection_rms_before", pixels_before.rms)
          .Add("reprojection_rms_after", pixels_after.rms);
    }
    if (!marginals_json.empty()) report.Add("marginals", marginals_json);
    if (!evaluation.empty()) report.AddObjectEntries(evaluation);
    if (!WriteFileAtomically(FLAGS_report, report.ToString() + "\n", &error)) {
      std::cerr << "slam optimize: " << error << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace slam
