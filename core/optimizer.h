// Global batch optimization of a Graph with Ceres.
//
// chi2 figures follow g2o (core/conventions.h): sum e^T Omega e, no 1/2.
#ifndef SLAM_CORE_OPTIMIZER_H_
#define SLAM_CORE_OPTIMIZER_H_

#include <ostream>
#include <string>

#include "core/graph.h"

namespace slam {

enum class SolverKind {
  kLevenbergMarquardt,  // Ceres trust region, LM strategy (default).
  kGaussNewton,         // LM with an effectively infinite trust region:
                        // every step is the Gauss-Newton step.
  kDogleg,              // Ceres trust region, traditional dogleg.
};
const char* SolverKindName(SolverKind kind);
bool ParseSolverKind(const std::string& text, SolverKind* kind);

struct OptimizerOptions {
  SolverKind solver = SolverKind::kLevenbergMarquardt;
  int max_iterations = 100;
  // Ceres' three convergence tests (see ceres::Solver::Options). With a
  // function tolerance of 1e-8 (relative decrease of the cost in the last
  // step) every benchmark graph ends within 3e-8 relative of its global
  // optimum; 1e-10 costs one more factorization on most graphs for digits
  // beyond that (sphere2500 0.79 s -> 0.67 s, torus3D 1.84 s -> 1.62 s).
  double function_tolerance = 1e-8;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-10;
  // "auto" picks sparse_schur when the graph has landmark (point) nodes that
  // no factor joins to each other and that hold at least half of the
  // unknowns (bundle adjustment), with all points in the first elimination
  // group (eliminated first), else sparse_normal_cholesky; any Schur solver
  // gets that grouping on graphs with points. Also
  // "dense_qr", "dense_normal_cholesky", "sparse_schur", "dense_schur",
  // "iterative_schur", "cgnr".
  std::string linear_solver = "auto";
  // Elimination order for the sparse Cholesky solvers: "auto" (for dense
  // factors, over 150 flops per entry, CHOLMOD picks the least fill of AMD,
  // METIS and NESDIS on the node graph, see core/ordering.h; sparse ones
  // keep Ceres' own AMD),
  // "amd", "metis", "nesdis", or "ceres" (Ceres' own).
  std::string ordering = "auto";
  // Sparse linear algebra behind the sparse solvers: "auto", "suite_sparse"
  // (CHOLMOD, supernodal on the system BLAS), "eigen_sparse" or "cx_sparse".
  // "auto" estimates the factor's density from the ordering analysis:
  // factors of over 150 flops per entry (3D spheres and tori) go to
  // CHOLMOD, where the supernodal BLAS kernels pay; sparser ones to Eigen's
  // simplicial LDLT, which does not depend on the BLAS (see Optimize).
  std::string sparse_library = "auto";
  // Sparse Cholesky chosen by "auto" whose factor would need more than
  // max_factor_bytes (0: half the physical memory) or cost more than
  // max_factor_flops per iteration (the estimate of the ordering analysis;
  // 1e12 is minutes per iteration on 2 cores): iterative_fallback switches to
  // conjugate gradients on the normal equations (CGNR, block-Jacobi
  // preconditioner, at most max_linear_solver_iterations per step), which
  // need memory of the order of the Jacobian; else the factorization runs.
  // Loop closures between far-apart times fill the factor (1M poses on a
  // 10 x 10 lattice: dense) but make conjugate gradients converge fast.
  double max_factor_bytes = 0.0;
  double max_factor_flops = 1e12;
  bool iterative_fallback = true;
  int max_linear_solver_iterations = 500;
  // LM/dogleg: initial trust-region radius (Ceres' default is 1e4). A large
  // radius lets the first steps be (nearly) Gauss-Newton steps, which from a
  // good initial guess saves many iterations (sphere2500 from the chordal
  // guess: 13 iterations at 1e4, 4 at 1e12); a rejected step still shrinks
  // it, so LM keeps its safeguard.
  double initial_trust_region_radius = 1e12;
  // Ceres' non-monotonic trust-region steps (accept a step that raises the
  // cost if the cost stays below the recent maximum): fewer iterations along
  // the curved valleys of landmark SLAM from dead reckoning.
  bool nonmonotonic_steps = false;
  // Pose graphs (no landmarks) under LM: when LM rejects its first 4 steps
  // (the Gauss-Newton step from the initial guess overshoots and LM has
  // shrunk its radius 1024 times), or its first 2 when the second is the
  // same step (damping negligible at the problem's scale), up to this many
  // plain Gauss-Newton steps follow, accepted even when the cost rises, as
  // g2o's Gauss-Newton; LM goes on from their best values when these are
  // below the start's (confirming in an iteration when Gauss-Newton
  // converged; from Ceres' default radius when, once below the start, a
  // step raised the cost), else from the untouched values (Gauss-Newton
  // diverged: still above the start after 3 steps).
  // LM alone crawls after such a radius collapse: dpgo's Intel from the
  // chordal guess took 91 iterations (Gauss-Newton: 4), M3500 with 0.2 rad
  // rotation noise 29. Other graphs run as before. 0 disables.
  // Once below the start, on 2D and 3D pose graphs, the probe's steps are
  // truncated Newton steps (the full Hessian by conjugate gradients
  // preconditioned with the Gauss-Newton factorization, in a trust region)
  // or the Gauss-Newton step when that is lower: with 0.3 rad of heading
  // noise Gauss-Newton's model (and LM's) converges linearly near the
  // optimum (27 iterations on a simulated grid world), Newton quadratically
  // (9). SE(3) blocks take Newton steps only with newton_under_way.
  int gauss_newton_probe_iterations = 20;
  // Pose graphs (2D and 3D) under LM: LM also stops for the probe's Newton
  // steps under way, after 4 rejections in a row or on a linear tail (3
  // accepted steps in a row whose relative decrease falls by a steady
  // factor, from iteration 8), also after a probe (at most 3 probes), and
  // the probe's Newton steps work on SE(3) blocks too: a 3D lattice with
  // 0.25 rad of rotation noise 42 -> 13 iterations. On for the batch pose
  // graph (`slam optimize`, OptimizeConfig); off here and in the frontends'
  // solves: the laser's loop decisions were seen to hang on where a loosely
  // stopped solve ends (LaserSlamTest's biased revisit, clang sanitizer
  // build, 2.7 m off with it), and converging every laser solve to rounding
  // instead cost 35 % of Intel's wall time (see the README, pose graphs).
  bool newton_under_way = false;
  // Ceres threads. One by default: on the 2-core machines measured, a second
  // thread made every benchmark slower (its hand-offs cost more than the
  // evaluation work it shares): intel 49 -> 42 ms, city10000 0.37 -> 0.34 s,
  // KITTI stereo BA 0.117 -> 0.095 s, Victoria Park 0.48 -> 0.47 s with one.
  int num_threads = 1;
  // Print one line per iteration and a final summary line to `progress`.
  bool verbose = true;
};

struct OptimizerSummary {
  double initial_chi2 = 0.0;         // sum e^T Omega e before.
  double final_chi2 = 0.0;           // ... after.
  double initial_robust_chi2 = 0.0;  // sum rho(e^T Omega e) before.
  double final_robust_chi2 = 0.0;
  int iterations = 0;               // Gauss-Newton probe + Ceres iterations.
  int gauss_newton_iterations = 0;  // Of which the probes' (all of them).
  bool converged = false;           // Stopped on a convergence test.
  bool usable = false;  // Result usable (converged or hit the limit).
  double solve_seconds = 0.0;
  // Where solve_seconds went, from Ceres' Solver::Summary summed over its
  // runs: Ceres' preprocessing (problem reduction, symbolic analysis),
  // evaluation of the residuals and of the Jacobians, and the linear
  // solver (factorization and solves). The rest of solve_seconds is the
  // ordering analysis, the Gauss-Newton probe, callbacks and chi2.
  double preprocess_seconds = 0.0;
  double residual_seconds = 0.0;
  double jacobian_seconds = 0.0;
  double linear_solver_seconds = 0.0;
  std::string linear_solver;         // What was used.
  std::string linear_solver_reason;  // Why, when "auto" chose by the graph.
  std::string ordering;              // Elimination ordering used.
  std::string sparse_library;        // Sparse linear algebra library used.
  std::string termination;           // Ceres' message.
  std::string gauge;                 // How the gauge freedom was removed.
  std::string full_report;           // Ceres' FullReport (timing breakdown).
  // The ordering analysis' estimate of the scalar factor's cost per
  // nonzero (flops / entries; 0 when no sparse Cholesky analysis ran):
  // what "auto" chose the sparse library by.
  double factor_flops_per_entry = 0.0;
};

// Optimizes the graph in place. The gauge (Graph::GaugeAnchors): fixed
// nodes and priors; every connected component without either gets its first
// node (lowest key) held constant.
OptimizerSummary Optimize(Graph* graph, const OptimizerOptions& options,
                          std::ostream* progress);

}  // namespace slam

#endif  // SLAM_CORE_OPTIMIZER_H_
