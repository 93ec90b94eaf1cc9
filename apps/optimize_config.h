// Settings of `slam optimize`: a plain struct with defaults, loaded from the
// `optimize:` section of a YAML file and printable back as YAML.
//
//   optimize:
//     init: auto            # auto | none | odometry | spanning_tree | chordal
//     solver: lm            # lm | gn | dogleg
//     max_iterations: 100
//     function_tolerance: 1e-8
//     gradient_tolerance: 1e-10
//     parameter_tolerance: 1e-10
//     initial_trust_region_radius: 1e12
//     nonmonotonic_steps: false
//     gauss_newton_probe_iterations: 20  # after LM rejects its first 4
//                           # steps on a pose graph (core/optimizer.h)
//     linear_solver: auto   # auto | sparse_normal_cholesky | sparse_schur |
//                           # dense_schur | iterative_schur | dense_qr | ...
//                           # (auto: sparse_schur with the landmarks
//                           # eliminated first when there are landmarks)
//     ordering: auto        # auto | amd | metis | nesdis | ceres
//     sparse_library: auto  # auto | suite_sparse | eigen_sparse | cx_sparse
//     max_factor_bytes: 0   # sparse factors (initialization and solver)
//     max_factor_flops: 1e12 # beyond these (0 bytes: half the memory) ...
//     iterative_fallback: true  # ... conjugate gradients, else the factor
//     max_linear_solver_iterations: 500  # CGNR steps (core/optimizer.h)
//     num_threads: 1        # Ceres threads (1 measured fastest on 2 cores)
//     verbose: true         # one line per iteration
//     repair_information: false
//     landmark_stages: 4    # landmark SLAM from dead reckoning: solve
//                           # growing halves of the trajectory first
//     robust:               # kernel per factor kind: KIND[:WIDTH]
//       odometry: none      # between factors of consecutive ids
//       loop_closure: none  # all other between factors
//       prior: none
//       landmark: none      # landmark and camera factors (pose-point)
//
// "auto" initialization: the chordal relaxation, unless the file's own guess
// already has a lower chi2 (the better of the two starts, as in the reference
// optima of the benchmark). With robust kernels the comparison is made under
// the kernels (sum of rho(e^T Omega e)), so that a relaxation corrupted by
// outlier loop closures loses to a dead-reckoning guess that is not.
#ifndef SLAM_APPS_OPTIMIZE_CONFIG_H_
#define SLAM_APPS_OPTIMIZE_CONFIG_H_

#include <string>

#include "core/graph.h"
#include "core/optimizer.h"
#include "factors/robust_kernels.h"

namespace slam {

struct OptimizeConfig {
  std::string init = "auto";
  // The batch pose graph lets LM stop for Newton steps under way (see
  // OptimizerOptions::newton_under_way; the frontends' solves keep it off).
  OptimizerOptions optimizer = [] {
    OptimizerOptions options;
    options.newton_under_way = true;
    return options;
  }();
  bool repair_information = false;
  // Landmark SLAM from dead reckoning (init auto chose the spanning tree of
  // an odometry tree, landmarks from their observations): solve the first
  // 1/2^(n-1), ..., 1/2 of the poses before the whole graph, re-placing the
  // later poses and landmarks after each (see OptimizeInStages in
  // frontends/posegraph/graph_solve.h). 1: one batch solve.
  int landmark_stages = 4;
  RobustKernelSpec robust_odometry;
  RobustKernelSpec robust_loop_closure;
  RobustKernelSpec robust_prior;
  RobustKernelSpec robust_landmark;
};

// Reads the `optimize:` section of the YAML file at `path` over *config.
// Unknown keys and bad values are errors naming the file and line.
bool LoadOptimizeConfig(const std::string& path, OptimizeConfig* config,
                        std::string* error);
// Checks values that YAML parsing alone cannot (names, ranges).
bool ValidateOptimizeConfig(const OptimizeConfig& config, std::string* error);
std::string OptimizeConfigToYaml(const OptimizeConfig& config);

// Sets each factor's robust kernel: robust_landmark on landmark factors,
// robust_prior on unary factors, robust_odometry between consecutive ids,
// robust_loop_closure between others.
void ApplyRobustKernels(const OptimizeConfig& config, Graph* graph);

}  // namespace slam

#endif  // SLAM_APPS_OPTIMIZE_CONFIG_H_
