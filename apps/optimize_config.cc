#include "apps/optimize_config.h"

#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include "apps/yaml_config.h"
#include "core/initialization.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

bool ReadKernel(const YAML::Node& node, const char* key,
                const std::string& where, RobustKernelSpec* spec,
                std::string* error) {
  std::string text = spec->ToString();
  if (!ReadOptional(node, key, where, &text, error)) return false;
  std::string parse_error;
  if (!ParseRobustKernel(text, spec, &parse_error)) {
    *error = where + ": robust." + key + ": " + parse_error;
    return false;
  }
  return true;
}

}  // namespace

bool LoadOptimizeConfig(const std::string& path, OptimizeConfig* config,
                        std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["optimize"];
  if (!node) return true;
  if (!CheckKnownKeys(node,
                      {"init",
                       "solver",
                       "max_iterations",
                       "function_tolerance",
                       "gradient_tolerance",
                       "parameter_tolerance",
                       "initial_trust_region_radius",
                       "linear_solver",
                       "ordering",
                       "sparse_library",
                       "num_threads",
                       "verbose",
                       "repair_information",
                       "robust",
                       "nonmonotonic_steps",
                       "landmark_stages",
                       "gauss_newton_probe_iterations",
                       "newton_under_way",
                       "max_factor_bytes",
                       "max_factor_flops",
                       "iterative_fallback",
                       "max_linear_solver_iterations"},
                      path, error)) {
    return false;
  }
  OptimizerOptions& o = config->optimizer;
  std::string solver = SolverKindName(o.solver);
  if (!ReadOptional(node, "init", path, &config->init, error) ||
      !ReadOptional(node, "solver", path, &solver, error) ||
      !ReadOptional(node, "max_iterations", path, &o.max_iterations, error) ||
      !ReadOptional(node, "function_tolerance", path, &o.function_tolerance,
                    error) ||
      !ReadOptional(node, "gradient_tolerance", path, &o.gradient_tolerance,
                    error) ||
      !ReadOptional(node, "parameter_tolerance", path, &o.parameter_tolerance,
                    error) ||
      !ReadOptional(node, "initial_trust_region_radius", path,
                    &o.initial_trust_region_radius, error) ||
      !ReadOptional(node, "nonmonotonic_steps", path, &o.nonmonotonic_steps,
                    error) ||
      !ReadOptional(node, "linear_solver", path, &o.linear_solver, error) ||
      !ReadOptional(node, "ordering", path, &o.ordering, error) ||
      !ReadOptional(node, "sparse_library", path, &o.sparse_library, error) ||
      !ReadOptional(node, "num_threads", path, &o.num_threads, error) ||
      !ReadOptional(node, "verbose", path, &o.verbose, error) ||
      !ReadOptional(node, "repair_information", path,
                    &config->repair_information, error) ||
      !ReadOptional(node, "landmark_stages", path, &config->landmark_stages,
                    error) ||
      !ReadOptional(node, "gauss_newton_probe_iterations", path,
                    &o.gauss_newton_probe_iterations, error) ||
      !ReadOptional(node, "newton_under_way", path, &o.newton_under_way,
                    error) ||
      !ReadOptional(node, "max_factor_bytes", path, &o.max_factor_bytes,
                    error) ||
      !ReadOptional(node, "max_factor_flops", path, &o.max_factor_flops,
                    error) ||
      !ReadOptional(node, "iterative_fallback", path, &o.iterative_fallback,
                    error) ||
      !ReadOptional(node, "max_linear_solver_iterations", path,
                    &o.max_linear_solver_iterations, error)) {
    return false;
  }
  if (!ParseSolverKind(solver, &o.solver)) {
    *error = path + ": optimize.solver '" + solver +
             "' is not one of lm, gn, dogleg";
    return false;
  }
  const YAML::Node robust = node["robust"];
  if (robust) {
    if (!CheckKnownKeys(robust,
                        {"odometry", "loop_closure", "prior", "landmark"}, path,
                        error) ||
        !ReadKernel(robust, "odometry", path, &config->robust_odometry,
                    error) ||
        !ReadKernel(robust, "loop_closure", path, &config->robust_loop_closure,
                    error) ||
        !ReadKernel(robust, "prior", path, &config->robust_prior, error) ||
        !ReadKernel(robust, "landmark", path, &config->robust_landmark,
                    error)) {
      return false;
    }
  }
  if (!ValidateOptimizeConfig(*config, error)) {
    *error = path + ": optimize." + *error;
    return false;
  }
  return true;
}

bool ValidateOptimizeConfig(const OptimizeConfig& config, std::string* error) {
  InitMethod method;
  if (config.init != "auto" && !ParseInitMethod(config.init, &method)) {
    *error = "init '" + config.init +
             "' is not one of auto, none, odometry, spanning_tree, chordal";
    return false;
  }
  const OptimizerOptions& o = config.optimizer;
  if (o.max_iterations < 0) {
    *error = "max_iterations must be >= 0";
    return false;
  }
  if (o.gauss_newton_probe_iterations < 0) {
    *error = "gauss_newton_probe_iterations must be >= 0";
    return false;
  }
  if (config.landmark_stages < 1) {
    *error = "landmark_stages must be >= 1";
    return false;
  }
  if (o.num_threads < 1) {
    *error = "num_threads must be >= 1";
    return false;
  }
  if (!(o.max_factor_bytes >= 0) || !(o.max_factor_flops > 0) ||
      o.max_linear_solver_iterations < 1) {
    *error =
        "max_factor_bytes must be >= 0, max_factor_flops > 0, "
        "max_linear_solver_iterations >= 1";
    return false;
  }
  if (o.linear_solver != "auto" &&
      o.linear_solver != "sparse_normal_cholesky" &&
      o.linear_solver != "dense_qr" &&
      o.linear_solver != "dense_normal_cholesky" &&
      o.linear_solver != "sparse_schur" && o.linear_solver != "dense_schur" &&
      o.linear_solver != "iterative_schur" && o.linear_solver != "cgnr") {
    *error = "linear_solver '" + o.linear_solver +
             "' is not one of auto, sparse_normal_cholesky, dense_qr, "
             "dense_normal_cholesky, sparse_schur, dense_schur, "
             "iterative_schur, cgnr";
    return false;
  }
  if (o.sparse_library != "auto" && o.sparse_library != "suite_sparse" &&
      o.sparse_library != "eigen_sparse" && o.sparse_library != "cx_sparse") {
    *error = "sparse_library '" + o.sparse_library +
             "' is not one of auto, suite_sparse, eigen_sparse, cx_sparse";
    return false;
  }
  if (!(o.initial_trust_region_radius > 0)) {
    *error = "initial_trust_region_radius must be > 0";
    return false;
  }
  if (o.ordering != "auto" && o.ordering != "amd" && o.ordering != "metis" &&
      o.ordering != "nesdis" && o.ordering != "ceres") {
    *error = "ordering '" + o.ordering +
             "' is not one of auto, amd, metis, nesdis, ceres";
    return false;
  }
  if (!(o.function_tolerance >= 0) || !(o.gradient_tolerance >= 0) ||
      !(o.parameter_tolerance >= 0)) {
    *error = "tolerances must be >= 0";
    return false;
  }
  return true;
}

std::string OptimizeConfigToYaml(const OptimizeConfig& config) {
  const OptimizerOptions& o = config.optimizer;
  std::ostringstream out;
  out.precision(17);
  out << "optimize:\n"
      << "  init: " << config.init << "\n"
      << "  solver: " << SolverKindName(o.solver) << "\n"
      << "  max_iterations: " << o.max_iterations << "\n"
      << "  function_tolerance: " << o.function_tolerance << "\n"
      << "  gradient_tolerance: " << o.gradient_tolerance << "\n"
      << "  parameter_tolerance: " << o.parameter_tolerance << "\n"
      << "  initial_trust_region_radius: " << o.initial_trust_region_radius
      << "\n"
      << "  nonmonotonic_steps: " << (o.nonmonotonic_steps ? "true" : "false")
      << "\n"
      << "  gauss_newton_probe_iterations: " << o.gauss_newton_probe_iterations
      << "\n"
      << "  newton_under_way: " << (o.newton_under_way ? "true" : "false")
      << "\n"
      << "  linear_solver: " << o.linear_solver << "\n"
      << "  ordering: " << o.ordering << "\n"
      << "  sparse_library: " << o.sparse_library << "\n"
      << "  max_factor_bytes: " << o.max_factor_bytes << "\n"
      << "  max_factor_flops: " << o.max_factor_flops << "\n"
      << "  iterative_fallback: " << (o.iterative_fallback ? "true" : "false")
      << "\n"
      << "  max_linear_solver_iterations: " << o.max_linear_solver_iterations
      << "\n"
      << "  num_threads: " << o.num_threads << "\n"
      << "  verbose: " << (o.verbose ? "true" : "false") << "\n"
      << "  repair_information: "
      << (config.repair_information ? "true" : "false") << "\n"
      << "  landmark_stages: " << config.landmark_stages << "\n"
      << "  robust:\n"
      << "    odometry: " << config.robust_odometry.ToString() << "\n"
      << "    loop_closure: " << config.robust_loop_closure.ToString() << "\n"
      << "    prior: " << config.robust_prior.ToString() << "\n"
      << "    landmark: " << config.robust_landmark.ToString() << "\n";
  return out.str();
}

namespace {

// Which robust kernel a factor gets.
const RobustKernelSpec& KernelFor(const OptimizeConfig& config,
                                  const Factor& factor) {
  if (IsLandmarkFactor(factor.type)) return config.robust_landmark;
  if (factor.keys.size() == 1) return config.robust_prior;
  const int64_t gap = factor.keys[1].id - factor.keys[0].id;
  return gap == 1 || gap == -1 ? config.robust_odometry
                               : config.robust_loop_closure;
}

}  // namespace

void ApplyRobustKernels(const OptimizeConfig& config, Graph* graph) {
  std::vector<std::pair<FactorId, std::shared_ptr<ceres::LossFunction>>> losses;
  for (const auto& [id, factor] : graph->factors()) {
    losses.emplace_back(id, MakeLoss(KernelFor(config, factor)));
  }
  for (auto& [id, loss] : losses) graph->SetLoss(id, std::move(loss));
}

}  // namespace slam
