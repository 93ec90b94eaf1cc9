// slam optimize: read a pose graph, initialize, optimize, write the result.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

#include <gflags/gflags.h>

#include "apps/certificate_report.h"
#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/json.h"
#include "apps/map_plot.h"
#include "apps/marginals_report.h"
#include "apps/optimize_config.h"
#include "apps/yaml_config.h"
#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/stereo_vo_io.h"
#include "datasets/trajectory_io.h"
#include "factors/landmark_factors.h"
#include "frontends/posegraph/graph_solve.h"

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

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
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
  if (!ParseMarginalIds(FLAGS_marginals, &marginal_ids, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 2;
  }

  // Fail before any work on outputs that cannot be written and on a ground
  // truth that cannot be read: a failed run leaves no output behind.
  for (const std::string& out : {FLAGS_o, FLAGS_report}) {
    if (!out.empty() && !CheckOutputFile(out, &error)) {
      std::cerr << "slam optimize: " << error << "\n";
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

  std::vector<Key> marginal_keys;
  if (!MarginalKeysOf(graph, marginal_ids, input, &marginal_keys, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 1;
  }

  ApplyRobustKernels(config, &graph);

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
  if (!InitializeGraph(config.init, landmarks_from_observations,
                       InitOptionsOf(config.optimizer), &graph, &init_used,
                       &error)) {
    std::cerr << "slam optimize: initialization failed: " << error << "\n";
    return 1;
  }
  const double init_seconds = Seconds(init_start);
  std::printf("initialization: %s, chi2 %.10g (%.3f s)\n", init_used.c_str(),
              graph.Chi2(), init_seconds);

  // Solve.
  // Landmark SLAM from dead reckoning: in stages (graph_solve.h).
  const bool staged = config.init == "auto" && init_used == "spanning_tree" &&
                      landmarks_from_observations;
  OptimizerSummary summary =
      OptimizeGraph(staged ? config.landmark_stages : 1, config.optimizer,
                    &graph, &std::cout);
  if (!summary.usable) {
    std::cerr << "slam optimize: the solver failed: " << summary.termination
              << "\n";
    return 1;
  }
  JsonObject certificate;
  if (!CertifyIfAsked(&graph, config.optimizer, &summary, &certificate,
                      &error)) {
    std::cerr << "slam optimize: " << error << "\n";
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

  JsonObject marginals_json;
  if (!ReportMarginals(&graph, marginal_keys, &marginals_json, &error)) {
    std::cerr << "slam optimize: " << error << "\n";
    return 1;
  }

  JsonObject evaluation;
  if (!FLAGS_gt.empty() &&
      !EvaluateGraphAgainstGroundTruth(graph, gt, FLAGS_gt, FLAGS_config,
                                       FLAGS_plot, &evaluation, &error)) {
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
        .Add("factor_flops_per_entry", summary.factor_flops_per_entry)
        .Add("ordering", summary.ordering)
        .Add("repaired_information", read_report.repaired_information)
        .Add("load_seconds", load_seconds)
        .Add("init_seconds", init_seconds)
        .Add("solve_seconds", summary.solve_seconds)
        .Add("write_seconds", write_seconds)
        .Add("total_seconds", total_seconds);
    JsonObject breakdown;
    const double accounted =
        summary.preprocess_seconds + summary.residual_seconds +
        summary.jacobian_seconds + summary.linear_solver_seconds;
    const int per = std::max(summary.iterations, 1);
    breakdown.Add("preprocess_seconds", summary.preprocess_seconds)
        .Add("residual_seconds", summary.residual_seconds)
        .Add("jacobian_seconds", summary.jacobian_seconds)
        .Add("linear_solver_seconds", summary.linear_solver_seconds)
        .Add("other_seconds", std::max(summary.solve_seconds - accounted, 0.0))
        .Add("jacobian_seconds_per_iteration", summary.jacobian_seconds / per)
        .Add("linear_solver_seconds_per_iteration",
             summary.linear_solver_seconds / per);
    report.Add("solve_breakdown", breakdown);
    if (num_points > 0) report.Add("landmarks", num_points);
    if (pixels_before.factors > 0) {
      report.Add("reprojection_rms_before", pixels_before.rms)
          .Add("reprojection_rms_after", pixels_after.rms);
    }
    if (!certificate.empty()) report.Add("certificate", certificate);
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
