#include "core/optimizer.h"

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "ceres/iteration_callback.h"
#include "ceres/ordered_groups.h"
#include "ceres/problem.h"
#include "ceres/solver.h"
#include "core/openmp_scope.h"
#include "core/ordering.h"

namespace slam {
namespace {

class ProgressPrinter : public ceres::IterationCallback {
 public:
  explicit ProgressPrinter(std::ostream* out) : out_(out) {}
  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& s) override {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "iter %4d  chi2 %-18.10g  dchi2 %-12.4g  |step| %-11.4g "
                  "radius %-9.3g %s  %8.4f s",
                  s.iteration, CeresCostToChi2(s.cost),
                  CeresCostToChi2(s.cost_change), s.step_norm,
                  s.trust_region_radius,
                  s.iteration == 0       ? "    "
                  : s.step_is_successful ? "ok  "
                                         : "rej ",
                  s.cumulative_time_in_seconds);
    *out_ << line << "\n";
    out_->flush();
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::ostream* out_;
};

bool HasPrior(const Graph& graph) {
  for (const auto& [id, f] : graph.factors()) {
    if (f.keys.size() == 1) return true;
  }
  return false;
}

bool IsPoint(const Key& key) {
  return key.kind == NodeKind::kPoint2 || key.kind == NodeKind::kPoint3;
}

// Landmark graphs for the Schur solvers: point nodes present and no factor
// joining two points (the points must form an independent set).
bool HasEliminablePoints(const Graph& graph) {
  bool any = false;
  for (const auto& [key, node] : graph.nodes()) any = any || IsPoint(key);
  if (!any) return false;
  for (const auto& [id, f] : graph.factors()) {
    int points = 0;
    for (const Key& k : f.keys) points += IsPoint(k) ? 1 : 0;
    if (points > 1) return false;
  }
  return true;
}

bool IsSchur(ceres::LinearSolverType type) {
  return type == ceres::SPARSE_SCHUR || type == ceres::DENSE_SCHUR ||
         type == ceres::ITERATIVE_SCHUR;
}

// Elimination groups for the Schur solvers: all points first (group 0), then
// everything else.
void SetSchurOrdering(const Graph& graph,
                      ceres::Solver::Options* solver_options) {
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (const auto& [key, node] : graph.nodes()) {
    ordering->AddElementToGroup(const_cast<double*>(node->value.data()),
                                IsPoint(key) ? 0 : 1);
  }
  solver_options->linear_solver_ordering = ordering;
}

ceres::LinearSolverType LinearSolverFromName(const std::string& name,
                                             bool* ok) {
  *ok = true;
  if (name == "auto" || name == "sparse_normal_cholesky") {
    return ceres::SPARSE_NORMAL_CHOLESKY;
  }
  if (name == "dense_qr") return ceres::DENSE_QR;
  if (name == "dense_normal_cholesky") return ceres::DENSE_NORMAL_CHOLESKY;
  if (name == "sparse_schur") return ceres::SPARSE_SCHUR;
  if (name == "dense_schur") return ceres::DENSE_SCHUR;
  if (name == "iterative_schur") return ceres::ITERATIVE_SCHUR;
  if (name == "cgnr") return ceres::CGNR;
  *ok = false;
  return ceres::SPARSE_NORMAL_CHOLESKY;
}

// Hands Ceres a complete elimination order computed by CHOLMOD.
bool SetOrdering(const Graph& graph, const std::string& method,
                 ceres::Solver::Options* solver_options, std::string* used,
                 double* flops_per_entry, std::string* error) {
  std::map<Key, int> index;
  std::vector<double*> blocks;
  for (const auto& [key, node] : graph.nodes()) {
    index[key] = static_cast<int>(blocks.size());
    blocks.push_back(const_cast<double*>(node->value.data()));
  }
  std::vector<std::pair<int, int>> edges;
  for (const auto& [id, f] : graph.factors()) {
    for (size_t a = 0; a < f.keys.size(); ++a) {
      for (size_t b = a + 1; b < f.keys.size(); ++b) {
        edges.emplace_back(index[f.keys[a]], index[f.keys[b]]);
      }
    }
  }
  OrderingResult result;
  if (!FillReducingOrdering(static_cast<int>(blocks.size()), edges, method,
                            &result, error)) {
    return false;
  }
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t k = 0; k < result.order.size(); ++k) {
    ordering->AddElementToGroup(blocks[result.order[k]], static_cast<int>(k));
  }
  solver_options->linear_solver_ordering = ordering;
  *used = result.method;
  // Flops per factor entry, scaled from the node level to scalars by the
  // mean block size: CHOLMOD's own supernodal-versus-simplicial measure.
  double dofs = 0.0;
  for (const auto& [key, node] : graph.nodes()) {
    dofs += TangentSize(key.kind) > 0 ? TangentSize(key.kind)
                                      : static_cast<int>(node->value.size());
  }
  *flops_per_entry = result.factor_nonzeros > 0
                         ? result.factor_flops / result.factor_nonzeros * dofs /
                               static_cast<double>(blocks.size())
                         : 0.0;
  return true;
}

}  // namespace

const char* SolverKindName(SolverKind kind) {
  switch (kind) {
    case SolverKind::kLevenbergMarquardt:
      return "lm";
    case SolverKind::kGaussNewton:
      return "gn";
    case SolverKind::kDogleg:
      return "dogleg";
  }
  return "lm";
}

bool ParseSolverKind(const std::string& text, SolverKind* kind) {
  if (text == "lm") {
    *kind = SolverKind::kLevenbergMarquardt;
  } else if (text == "gn") {
    *kind = SolverKind::kGaussNewton;
  } else if (text == "dogleg") {
    *kind = SolverKind::kDogleg;
  } else {
    return false;
  }
  return true;
}

OptimizerSummary Optimize(Graph* graph, const OptimizerOptions& options,
                          std::ostream* progress) {
  OptimizerSummary summary;
  const auto start = std::chrono::steady_clock::now();
  graph->Chi2AndRobustChi2(&summary.initial_chi2, &summary.initial_robust_chi2);

  ceres::Problem problem(Graph::ProblemOptions());
  graph->BuildProblem(&problem);
  const std::vector<Key> anchors = graph->GaugeAnchors();
  for (const Key& key : anchors) {
    problem.SetParameterBlockConstant(graph->FindNode(key)->value.data());
  }
  if (anchors.empty()) {
    summary.gauge = graph->HasFixedNode() ? "fixed nodes" : "prior factors";
  } else if (anchors.size() == 1 && !graph->HasFixedNode() &&
             !HasPrior(*graph)) {
    summary.gauge = "first node " + anchors[0].ToString() + " held constant";
  } else {
    summary.gauge = "fixed nodes/priors, and the first node of " +
                    std::to_string(anchors.size()) +
                    " otherwise unanchored component(s) held constant";
  }

  ceres::Solver::Options solver_options;
  bool linear_ok = true;
  solver_options.linear_solver_type =
      LinearSolverFromName(options.linear_solver, &linear_ok);
  if (!linear_ok) {
    summary.termination =
        "unknown linear solver '" + options.linear_solver + "'";
    return summary;
  }
  if (options.sparse_library != "auto" &&
      options.sparse_library != "eigen_sparse" &&
      options.sparse_library != "cx_sparse" &&
      options.sparse_library != "suite_sparse") {
    summary.termination =
        "unknown sparse library '" + options.sparse_library + "'";
    return summary;
  }
  const bool landmarks = HasEliminablePoints(*graph);
  if (options.linear_solver == "auto" && landmarks) {
    // Eliminating the points pays when they hold most of the unknowns
    // (bundle adjustment: KITTI stereo, 26 cameras and 3000+ points). With
    // few landmarks seen from thousands of poses (Victoria Park: 151
    // landmarks, 6969 poses) the reduced pose system fills in where a
    // landmark links many poses, and sparse Cholesky on the whole system is
    // about ten times faster per iteration (measured).
    int point_dofs = 0, other_dofs = 0;
    for (const auto& [key, node] : graph->nodes()) {
      (IsPoint(key) ? point_dofs : other_dofs) += TangentSize(key.kind);
    }
    if (point_dofs >= other_dofs) {
      solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
      summary.linear_solver_reason =
          "auto: landmarks hold most unknowns, Schur complement";
    } else {
      summary.linear_solver_reason =
          "auto: landmarks hold few unknowns, sparse Cholesky on all";
    }
  }
  if (IsSchur(solver_options.linear_solver_type) && landmarks) {
    SetSchurOrdering(*graph, &solver_options);
    summary.ordering = "schur: points eliminated first";
  }
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.num_threads = options.num_threads;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.logging_type = ceres::SILENT;
  solver_options.initial_trust_region_radius =
      options.initial_trust_region_radius;
  solver_options.use_nonmonotonic_steps = options.nonmonotonic_steps;
  switch (options.solver) {
    case SolverKind::kLevenbergMarquardt:
      solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
      break;
    case SolverKind::kGaussNewton:
      solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
      solver_options.initial_trust_region_radius = 1e16;
      solver_options.max_trust_region_radius = 1e16;
      solver_options.min_lm_diagonal = 1e-32;
      solver_options.max_lm_diagonal = 1e-32;
      break;
    case SolverKind::kDogleg:
      solver_options.trust_region_strategy_type = ceres::DOGLEG;
      break;
  }
  const bool sparse_cholesky =
      solver_options.linear_solver_type == ceres::SPARSE_NORMAL_CHOLESKY;
  // 1. A cheap AMD analysis of the node graph estimates the factor's
  //    density, which picks the sparse library ("auto").
  // 2. Dense factors (CHOLMOD supernodal) get the least-fill ordering of
  //    AMD, METIS and NESDIS; sparse ones keep Ceres' own AMD ordering.
  // Above ~150 flops per factor entry CHOLMOD's supernodal kernels win
  // (measured on the benchmark graphs: tori and spheres above, 2D graphs
  // and parking-garage below).
  constexpr double kSupernodalFlopsPerEntry = 150.0;
  if (summary.ordering.empty()) summary.ordering = "ceres";
  summary.sparse_library = options.sparse_library;
  if (sparse_cholesky && graph->NumNodes() > 1) {
    std::string ordering_error;
    double flops_per_entry = 0.0;
    std::string method;
    ceres::Solver::Options analysis_only;
    if (options.sparse_library == "auto") {
      if (!SetOrdering(*graph, "amd", &analysis_only, &method, &flops_per_entry,
                       &ordering_error)) {
        summary.termination = ordering_error;
        return summary;
      }
      summary.sparse_library = flops_per_entry > kSupernodalFlopsPerEntry
                                   ? "suite_sparse"
                                   : "eigen_sparse";
    }
    const bool dense = summary.sparse_library == "suite_sparse";
    const std::string wanted = options.ordering == "auto"
                                   ? (dense ? "auto" : "ceres")
                                   : options.ordering;
    if (wanted != "ceres") {
      if (!SetOrdering(*graph, wanted, &solver_options, &summary.ordering,
                       &flops_per_entry, &ordering_error)) {
        summary.termination = ordering_error;
        return summary;
      }
    }
  } else if (summary.sparse_library == "auto") {
    summary.sparse_library = "suite_sparse";
  }
  solver_options.sparse_linear_algebra_library_type =
      summary.sparse_library == "eigen_sparse" ? ceres::EIGEN_SPARSE
      : summary.sparse_library == "cx_sparse"  ? ceres::CX_SPARSE
                                               : ceres::SUITE_SPARSE;
  ProgressPrinter printer(progress);
  if (options.verbose && progress != nullptr) {
    solver_options.callbacks.push_back(&printer);
  }

  ceres::Solver::Summary ceres_summary;
  {
    const SerialOpenMpScope serial_openmp;
    ceres::Solve(solver_options, &problem, &ceres_summary);
  }

  summary.iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
  summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  summary.usable = ceres_summary.IsSolutionUsable();
  summary.termination = ceres_summary.message;
  summary.full_report = ceres_summary.FullReport();
  summary.linear_solver =
      ceres::LinearSolverTypeToString(ceres_summary.linear_solver_type_used);
  graph->Chi2AndRobustChi2(&summary.final_chi2, &summary.final_robust_chi2);
  summary.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (options.verbose && progress != nullptr) {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "done: %d iterations, chi2 %.10g -> %.10g, %.4f s, %s (%s)",
                  summary.iterations, summary.initial_chi2, summary.final_chi2,
                  summary.solve_seconds,
                  summary.converged ? "converged" : "NOT converged",
                  summary.termination.c_str());
    *progress << line << "\n";
  }
  return summary;
}

}  // namespace slam
