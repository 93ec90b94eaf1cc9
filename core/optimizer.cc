#include "core/optimizer.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ceres/crs_matrix.h"
#include "ceres/iteration_callback.h"
#include "ceres/manifold.h"
#include "ceres/ordered_groups.h"
#include "ceres/problem.h"
#include "ceres/solver.h"
#include "core/lie.h"
#include "core/manifolds.h"
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

// The scalar sparse factor of an elimination order, estimated from its node
// graph's (node-level counts scaled by the mean block size).
struct FactorEstimate {
  double nonzeros = 0.0;
  double flops = 0.0;
  double flops_per_entry = 0.0;
};

// Hands Ceres a complete elimination order computed by CHOLMOD.
bool SetOrdering(const Graph& graph, const std::string& method,
                 ceres::Solver::Options* solver_options, std::string* used,
                 FactorEstimate* estimate, std::string* error) {
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
  const double block = dofs / static_cast<double>(blocks.size());
  estimate->nonzeros = result.factor_nonzeros * block * block;
  estimate->flops = result.factor_flops * block * block * block;
  estimate->flops_per_entry =
      result.factor_nonzeros > 0
          ? result.factor_flops / result.factor_nonzeros * block
          : 0.0;
  return true;
}

// Stops Ceres when its first kRejectionsBeforeProbe steps are all rejected
// (see Optimize): by then LM has shrunk its radius 2 * 4 * 8 * 16 = 1024
// times. Fewer rejections (parking-garage 3, MIT 2) LM recovers from in an
// iteration or two, cheaper than the restart.
constexpr int kRejectionsBeforeProbe = 4;
// LM's initial radius after a Gauss-Newton probe that stalled (Ceres'
// default radius).
constexpr double kRadiusAfterStall = 1e4;

// LM's linear tail: kLinearStepsBeforeNewton accepted steps in a row whose
// relative decrease is between kLinearRateLow and kLinearRateHigh times the
// previous one's, from iteration kIterationsBeforeLinearTail on (the
// benchmark graphs converge within 7 iterations, except GTSAM's
// pose3example: 30, halving its decrease per step). A 3D grid world with
// 0.2 rad rotation noise: LM (Gauss-Newton: the radius grows to 1e16)
// halves its decrease per step from iteration 10 to 27.
constexpr int kIterationsBeforeLinearTail = 8;
constexpr int kLinearStepsBeforeNewton = 3;
constexpr double kLinearRateLow = 0.25;
constexpr double kLinearRateHigh = 0.9;
// Probes (and LM runs after them) at most per solve.
constexpr int kMaxProbes = 3;
// Relative cost changes below this are rounding (converged), not a tail.
constexpr double kRoundingLevel = 1e-10;

class FirstStepWatcher : public ceres::IterationCallback {
 public:
  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& s) override {
    if (s.iteration == 0) return ceres::SOLVER_CONTINUE;
    if (s.step_is_successful) {
      done_ = true;
      rejections_in_a_row_ = 0;
      // Linear convergence: the relative decrease falls by a steady factor
      // per accepted step (Gauss-Newton's rate where the second-order term
      // it drops is of the order of J^T J: about halving).
      const double relative = s.cost_change / (s.cost + s.cost_change);
      const double rate = relative / previous_relative_;
      previous_relative_ = relative;
      linear_steps_ = rate > kLinearRateLow && rate < kLinearRateHigh
                          ? linear_steps_ + 1
                          : 0;
      if (newton_midway_ && s.iteration >= kIterationsBeforeLinearTail &&
          linear_steps_ >= kLinearStepsBeforeNewton &&
          relative > kRoundingLevel) {
        stalled_midway_ = true;
        midway_reason_ = "LM converges linearly";
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
      return ceres::SOLVER_CONTINUE;
    }
    // Under way, kRejectionsBeforeProbe rejections in a row: Gauss-Newton's
    // model (LM's, damped) no longer predicts the cost, LM's radius has
    // shrunk 1024 times, and LM crawls from there (a grid world with 0.35
    // rad heading noise: 8 rejections after 3 accepted steps, then 45 short
    // steps). Where the probe takes Newton steps (pose graphs), LM stops
    // for them.
    if (done_) {
      // Rejections at the rounding level of the cost are convergence.
      const bool significant = -s.cost_change > kRoundingLevel * s.cost;
      rejections_in_a_row_ = significant ? rejections_in_a_row_ + 1 : 0;
      if (newton_midway_ && rejections_in_a_row_ == kRejectionsBeforeProbe) {
        stalled_midway_ = true;
        midway_reason_ = "LM rejected 4 steps in a row";
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
      return ceres::SOLVER_CONTINUE;
    }
    // The second rejected step equal to the first (same length, same
    // cost): the damping is still negligible at the problem's scale, and
    // LM would reject the same Gauss-Newton step until the radius has
    // shrunk by orders of magnitude (grid worlds with 0.2-0.3 rad heading
    // noise: four identical rejections).
    const bool same_step =
        s.iteration == 2 &&
        std::abs(s.step_norm - first_step_norm_) <= 1e-2 * first_step_norm_ &&
        std::abs(s.cost_change - first_cost_change_) <=
            1e-2 * std::abs(first_cost_change_);
    if (s.iteration == 1) {
      first_step_norm_ = s.step_norm;
      first_cost_change_ = s.cost_change;
    }
    if (!done_ && (same_step || s.iteration == kRejectionsBeforeProbe)) {
      rejected_ = true;
      rejections_ = s.iteration;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }
  // For LM's run after a probe: watches for a stall or a linear tail under
  // way only.
  void WatchUnderWay() {
    done_ = true;
    rejected_ = false;
    stalled_midway_ = false;
    rejections_in_a_row_ = 0;
    linear_steps_ = 0;
    previous_relative_ = 0.0;
  }
  // Lets LM stop for the probe after rejections in a row under way too.
  void set_newton_midway(bool newton_midway) { newton_midway_ = newton_midway; }
  bool stalled_midway() const { return stalled_midway_; }
  const char* midway_reason() const { return midway_reason_; }
  bool first_steps_rejected() const { return rejected_; }
  int rejections() const { return rejections_; }

 private:
  bool done_ = false;  // A step was accepted: LM is under way.
  bool newton_midway_ = false;
  bool stalled_midway_ = false;
  int rejections_in_a_row_ = 0;
  double previous_relative_ = 0.0;
  int linear_steps_ = 0;
  const char* midway_reason_ = "";
  bool rejected_ = false;
  int rejections_ = 0;
  double first_step_norm_ = 0.0;
  double first_cost_change_ = 0.0;
};

// Conjugate-gradient iterations per Newton step of the probe (10 gave the
// same iteration counts on the grid worlds of posegraph_tails_test, and the
// noisy M3500's solve took 2.7 times plain Gauss-Newton's instead of 1.5).
constexpr int kNewtonCgIterations = 4;
// Halvings of a Newton step that raised the cost.
constexpr int kNewtonHalvings = 3;

// A truncated Newton step: preconditioned conjugate gradients on H dx = -g,
// H the full Hessian (products by `hessian_times`), preconditioned by the
// Gauss-Newton factorization J^T J = `preconditioner`, from dx = 0. On pose
// graphs with large residuals (0.3 rad heading noise on a lattice) the
// second-order term sum r_i H_i that Gauss-Newton drops is of the order of
// J^T J along the weakly constrained rotation modes: Gauss-Newton (and LM,
// whose model it is) converges linearly there, about halving the error per
// factorization. The preconditioned operator is I plus a few outlying
// eigenvalues, which conjugate gradients resolve in a few products (each
// one gradient evaluation and one pair of triangular solves, no new
// factorization). Its first iterate is the Gauss-Newton step (*dx on entry)
// scaled to the Newton model's minimum along it. Steihaug's truncation keeps
// the step within `radius`: stops at a relative residual of 1e-3, after
// `max_iterations`, or on the boundary (reached, or non-positive curvature
// met). Returns the number of products; `predicted_decrease` is the model's.
template <typename Factorization, typename HessianTimes>
int NewtonStep(const Eigen::VectorXd& g, const Factorization& preconditioner,
               int max_iterations, double radius,
               const HessianTimes& hessian_times, Eigen::VectorXd* dx,
               double* predicted_decrease) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(g.size());
  Eigen::VectorXd r = -g;
  Eigen::VectorXd z = *dx;  // M^-1 r: the Gauss-Newton step.
  Eigen::VectorXd p = z;
  double rz = r.dot(z);
  const double r0 = r.norm();
  int products = 0;
  for (int k = 0; k < max_iterations; ++k) {
    const Eigen::VectorXd hp = hessian_times(p);
    ++products;
    const double curvature = p.dot(hp);
    if (!hp.allFinite()) break;
    const double alpha = curvature > 0.0 ? rz / curvature : 0.0;
    if (!(p.squaredNorm() > 0.0)) break;
    if (curvature <= 0.0 || (x + alpha * p).norm() >= radius) {
      // To the boundary along p (Steihaug): tau >= 0 with |x + tau p| = r.
      const double pp = p.squaredNorm(), xp = x.dot(p);
      const double tau =
          (-xp +
           std::sqrt(xp * xp + pp * (radius * radius - x.squaredNorm()))) /
          pp;
      x += tau * p;
      r -= tau * hp;
      break;
    }
    x += alpha * p;
    r -= alpha * hp;
    if (r.norm() <= 1e-3 * r0) break;
    z = preconditioner.solve(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  // The model's decrease -(g.x + x.Hx / 2), with Hx = -g - r.
  *predicted_decrease = 0.5 * (x.dot(r) - g.dot(x));
  if (x.allFinite() && x.squaredNorm() > 0.0) *dx = x;
  return products;
}

// Whether the probe's Hessian products know the block's frame transport
// (hessian_times in GaussNewtonProbe): Euclidean, SE(2) and SE(3) blocks.
bool NewtonTransports(const ceres::Manifold* manifold) {
  return manifold == nullptr ||
         dynamic_cast<const SE2Manifold*>(manifold) != nullptr ||
         dynamic_cast<const SE3Manifold*>(manifold) != nullptr;
}

struct ProbeResult {
  int cg_iterations = 0;   // Hessian products of the Newton steps.
  bool converged = false;  // Relative decrease below the tolerance.
  bool improved = false;   // Values kept: their cost is below the start's.
  bool stalled = false;    // Stopped when the cost rose below the start.
  int iterations = 0;
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
};

// Plain Gauss-Newton (every step taken, as g2o's Gauss-Newton) on the
// problem's free blocks, from their current values. LM rejects a first
// Gauss-Newton step that raises the cost, shrinks its radius by orders of
// magnitude and then crawls along a weakly constrained direction (dpgo's
// Intel from the chordal guess: 91 iterations; Gauss-Newton overshoots once
// and is at the optimum two steps later). Stops when the relative decrease
// falls below `tolerance`, after `max_iterations`, or when the cost is still
// above the start's after three steps (diverging); keeps the values when
// their cost is below the start's, else restores the starting values.
ProbeResult GaussNewtonProbe(ceres::Problem* problem,
                             const std::vector<double*>& blocks,
                             int max_iterations, double tolerance,
                             bool newton_from_start, bool newton_on_se3,
                             std::ostream* progress) {
  ProbeResult result;
  std::vector<int> sizes, tangent_sizes, offsets;
  std::vector<double> saved;
  int tangent_total = 0;
  for (double* block : blocks) {
    sizes.push_back(problem->ParameterBlockSize(block));
    tangent_sizes.push_back(problem->ParameterBlockTangentSize(block));
    offsets.push_back(tangent_total);
    tangent_total += tangent_sizes.back();
    saved.insert(saved.end(), block, block + sizes.back());
  }
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = blocks;
  evaluate.num_threads = 1;
  using SparseMatrix = Eigen::SparseMatrix<double>;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>
      ldlt;
  double cost = 0.0;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(evaluate, &cost, &residuals, nullptr, &crs)) {
    return result;
  }
  result.initial_chi2 = CeresCostToChi2(cost);
  const double start_cost = cost;
  // The lowest-cost values seen (the start's are in `saved`).
  std::vector<double> best = saved;
  double best_cost = start_cost;
  auto copy_in = [&](const std::vector<double>& values) {
    size_t k = 0;
    for (size_t b = 0; b < blocks.size(); ++b) {
      std::copy(values.begin() + k, values.begin() + k + sizes[b], blocks[b]);
      k += sizes[b];
    }
  };
  auto copy_out = [&](std::vector<double>* values) {
    size_t k = 0;
    for (size_t b = 0; b < blocks.size(); ++b) {
      std::copy(blocks[b], blocks[b] + sizes[b], values->begin() + k);
      k += sizes[b];
    }
  };
  std::vector<double> x_plus;
  // x <- x [+] delta, block by block on the problem's manifolds.
  const auto apply = [&](const Eigen::VectorXd& dx) {
    for (size_t b = 0; b < blocks.size(); ++b) {
      x_plus.resize(sizes[b]);
      const double* delta = dx.data() + offsets[b];
      const ceres::Manifold* manifold = problem->GetManifold(blocks[b]);
      if (manifold != nullptr) {
        manifold->Plus(blocks[b], delta, x_plus.data());
      } else {
        for (int k = 0; k < sizes[b]; ++k) x_plus[k] = blocks[b][k] + delta[k];
      }
      std::copy(x_plus.begin(), x_plus.end(), blocks[b]);
    }
  };
  std::vector<double> here = saved;  // The current values, for Newton.
  double radius = 0.0;               // Newton's trust region; 0: not yet set.
  // Newton steps where the Hessian products are exact up to the difference:
  // 2D and 3D poses and Euclidean blocks (other manifolds would need their
  // own frame transport, see hessian_times).
  std::vector<bool> se2(blocks.size(), false), se3(blocks.size(), false);
  bool newton = true;
  for (size_t b = 0; b < blocks.size(); ++b) {
    const ceres::Manifold* manifold = problem->GetManifold(blocks[b]);
    se2[b] = dynamic_cast<const SE2Manifold*>(manifold) != nullptr;
    se3[b] = dynamic_cast<const SE3Manifold*>(manifold) != nullptr;
    newton = newton && NewtonTransports(manifold) && (newton_on_se3 || !se3[b]);
  }
  Eigen::Index analysed_nonzeros = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> j(
        crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()),
        crs.rows.data(), crs.cols.data(), crs.values.data());
    const Eigen::Map<const Eigen::VectorXd> r(residuals.data(),
                                              residuals.size());
    const SparseMatrix jt = j.transpose();
    const SparseMatrix h = jt * j;
    const Eigen::VectorXd g = jt * r;
    // Structural pattern (no pruning): analysed once, unless it changed.
    if (it == 1 || h.nonZeros() != analysed_nonzeros) {
      ldlt.analyzePattern(h);
      analysed_nonzeros = h.nonZeros();
    }
    ldlt.factorize(h);
    if (ldlt.info() != Eigen::Success) break;
    Eigen::VectorXd dx = ldlt.solve(-g);
    if (!dx.allFinite()) break;
    // Below the start: a truncated Newton step, conjugate gradients on the
    // full Hessian preconditioned by the Gauss-Newton factorization (see
    // NewtonStep) in a trust region that starts at the length of the first
    // such Gauss-Newton step. Above the start (Gauss-Newton's overshoot from
    // the initial guess) plain Gauss-Newton steps, as before.
    bool newton_taken = false;
    if (newton && (cost < start_cost || newton_from_start)) {
      copy_out(&here);
      const auto hessian_times = [&](const Eigen::VectorXd& v) {
        // Forward difference of the gradient along v, each unknown moved by
        // 1e-6 in the root mean square (radians, metres): about the square
        // root of the rounding of the gradient's sums.
        const double eps = 1e-6 * std::sqrt(static_cast<double>(v.size())) /
                           std::max(v.norm(), 1e-300);
        apply(eps * v);
        double unused = 0.0;
        std::vector<double> gradient;
        problem->Evaluate(evaluate, &unused, nullptr, &gradient, nullptr);
        copy_in(here);
        // The gradient of the pullback f(x [+] delta) at delta = eps v, so
        // that the products are those of one symmetric Hessian: Ceres'
        // gradient at x [+] eps v is in that point's tangent frame, whose
        // translation axes turned by eps v_theta.
        Eigen::Map<Eigen::VectorXd> g_plus(gradient.data(), gradient.size());
        for (size_t b = 0; b < blocks.size(); ++b) {
          if (se3[b]) {
            // SE(3): (t + R(q) rho, q Exp(phi)); the translation gradient
            // turned by Exp(eps v_phi), the rotation's through the right
            // Jacobian: q Exp(phi + d) ~ q Exp(phi) Exp(Jr(phi) d).
            const Eigen::Vector3d phi = eps * v.segment<3>(offsets[b] + 3);
            auto rho = g_plus.segment<3>(offsets[b]);
            auto rot = g_plus.segment<3>(offsets[b] + 3);
            rho = QuaternionExp<double>(phi).toRotationMatrix() *
                  Eigen::Vector3d(rho);
            rot = RightJacobianSO3(phi).transpose() * Eigen::Vector3d(rot);
            continue;
          }
          if (!se2[b]) continue;
          const double angle = eps * v(offsets[b] + 2);
          const double c = std::cos(angle), s = std::sin(angle);
          const double gx = g_plus(offsets[b]), gy = g_plus(offsets[b] + 1);
          g_plus(offsets[b]) = c * gx - s * gy;
          g_plus(offsets[b] + 1) = s * gx + c * gy;
        }
        return Eigen::VectorXd((g_plus - g) / eps);
      };
      const Eigen::VectorXd gauss_newton = dx;
      if (radius <= 0.0) radius = gauss_newton.norm();
      double predicted = 0.0;
      result.cg_iterations += NewtonStep(g, ldlt, kNewtonCgIterations, radius,
                                         hessian_times, &dx, &predicted);
      // The step raised the cost (its quadratic model is poor that far, or
      // the Hessian indefinite): halved up to kNewtonHalvings times (cost
      // evaluations only), else the Gauss-Newton step. The radius follows
      // the model's agreement, as in a trust-region method.
      // Where Gauss-Newton's model is good (small residuals: the noisy
      // M3500) its step can do better than the truncated Newton step: the
      // lower of the two is taken (one more cost evaluation).
      const auto cost_after = [&](const Eigen::VectorXd& step) {
        apply(step);
        double c = 0.0;
        const bool ok =
            problem->Evaluate(evaluate, &c, nullptr, nullptr, nullptr);
        copy_in(here);
        return ok && std::isfinite(c) ? c
                                      : std::numeric_limits<double>::infinity();
      };
      bool newton_ok = false;
      double newton_cost = 0.0;
      for (int h = 0; h <= kNewtonHalvings && !newton_ok; ++h) {
        if (h > 0) dx *= 0.5;
        newton_cost = cost_after(dx);
        newton_ok = newton_cost < cost;
        if (h == 0) {
          const double ratio = (cost - newton_cost) / predicted;
          const double length = dx.norm();
          if (!(ratio > 0.25)) {
            radius = 0.25 * length;
          } else if (ratio > 0.75 && length >= 0.99 * radius) {
            radius = 2.0 * radius;
          }
        }
      }
      if (newton_ok && cost_after(gauss_newton) < newton_cost) {
        newton_ok = false;
      }
      // From LM's values under way the Gauss-Newton step is the one LM
      // rejected: the probe ends when Newton's does not lower the cost.
      if (!newton_ok && newton_from_start) break;
      if (!newton_ok) dx = gauss_newton;
      newton_taken = newton_ok;
    }
    apply(dx);
    const double previous = cost;
    if (!problem->Evaluate(evaluate, &cost, &residuals, nullptr, &crs) ||
        !std::isfinite(cost)) {
      break;
    }
    result.iterations = it;
    if (progress != nullptr) {
      char line[160];
      std::snprintf(line, sizeof(line),
                    "%s %4d  chi2 %-18.10g  dchi2 %-12.4g  |dx| %-11.4g",
                    newton_taken ? "newt" : "gn  ", it, CeresCostToChi2(cost),
                    CeresCostToChi2(previous - cost), dx.norm());
      *progress << line << "\n";
    }
    if (cost <= start_cost && cost <= previous &&
        previous - cost <= tolerance * previous) {
      result.converged = true;
      break;
    }
    if (cost < best_cost) {
      best_cost = cost;
      copy_out(&best);
    } else if (best_cost < start_cost) {
      // Below the start, then up again: near the optimum of a graph with
      // large residuals Gauss-Newton's model no longer descends (a grid
      // world with 0.3 rad heading noise: 2554.655 then five rising steps).
      // The best values are kept and LM goes on from them.
      result.stalled = true;
      break;
    }
    // Gauss-Newton may overshoot once or twice (Intel: 220 -> 249 -> 215.8);
    // still above the start after that, it is diverging.
    if (it >= 3 && cost >= start_cost) break;
  }
  if (result.converged) {
    result.improved = true;
    result.final_chi2 = CeresCostToChi2(cost);
  } else if (best_cost < start_cost) {
    copy_in(best);
    result.improved = true;
    result.final_chi2 = CeresCostToChi2(best_cost);
  } else {
    copy_in(saved);
  }
  return result;
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
  //    density (flops per factor entry), which picks the sparse library
  //    ("auto"): above 150 flops per entry CHOLMOD (3D spheres and tori),
  //    supernodal on the system BLAS; below, Eigen's simplicial LDL^T,
  //    which does not depend on the BLAS.
  // 2. Those dense factors get the least-fill ordering of AMD, METIS and
  //    NESDIS; the others keep Ceres' own AMD ordering.
  // Measured with OpenBLAS, CHOLMOD is also faster from about 50 flops per
  //    entry (parking-garage 54: solve 0.126 -> 0.092 s, city10000 83:
  //    0.19-0.22 -> 0.15 s), and 40 is CHOLMOD's own supernodal switch. Not
  //    adopted: laser SLAM's pose graphs of ACES played three times (80-117
  //    flops per entry) then solve on CHOLMOD and the BLAS, and with
  //    OpenBLAS that run registered one pass of the log 81 degrees off (42
  //    closures undone by the chi2 test, a map 40 % larger), where Eigen
  //    and CHOLMOD on ATLAS mapped it right: a rounding-level difference
  //    flipped a tracking decision at a fast turn (fixed in the laser
  //    tracking since; README, "Load"). Eigen keeps such runs independent
  //    of the BLAS.
  constexpr double kSupernodalFlopsPerEntry = 150.0;
  if (summary.ordering.empty()) summary.ordering = "ceres";
  summary.sparse_library = options.sparse_library;
  if (sparse_cholesky && graph->NumNodes() > 1) {
    std::string ordering_error;
    FactorEstimate estimate;
    std::string method;
    ceres::Solver::Options analysis_only;
    if (options.sparse_library == "auto") {
      if (!SetOrdering(*graph, "amd", &analysis_only, &method, &estimate,
                       &ordering_error)) {
        summary.termination = ordering_error;
        return summary;
      }
      summary.sparse_library =
          estimate.flops_per_entry > kSupernodalFlopsPerEntry ? "suite_sparse"
                                                              : "eigen_sparse";
      summary.factor_flops_per_entry = estimate.flops_per_entry;
    }
    // CHOLMOD (chosen or forced) gets the ordering search.
    const bool dense = summary.sparse_library == "suite_sparse";
    const std::string wanted = options.ordering == "auto"
                                   ? (dense ? "auto" : "ceres")
                                   : options.ordering;
    // 3. A factor beyond the memory or flops allowed: conjugate gradients
    //    on the normal equations (Ceres' CGNR, block-Jacobi preconditioner),
    //    which need memory of the order of the Jacobian only. When AMD's
    //    factor is over ten times beyond, no ordering brings it within
    //    (METIS and nested dissection gain 2-5x on grids) and the other
    //    orderings, slow on such graphs, are not tried.
    const auto excess = [&](const FactorEstimate& e) {
      return FactorExcess(e.nonzeros, e.flops, options.max_factor_bytes,
                          options.max_factor_flops);
    };
    const bool may_fall_back =
        options.linear_solver == "auto" && options.iterative_fallback;
    const bool hopeless = may_fall_back && excess(estimate) > kNoOrderingHelps;
    std::string estimated_with = method;
    if (wanted != "ceres" && !hopeless) {
      if (!SetOrdering(*graph, wanted, &solver_options, &summary.ordering,
                       &estimate, &ordering_error)) {
        summary.termination = ordering_error;
        return summary;
      }
      estimated_with = summary.ordering;
    }
    if (may_fall_back && estimate.nonzeros > 0.0 && excess(estimate) > 1.0) {
      char text[300];
      std::snprintf(text, sizeof(text),
                    "auto: the sparse factor would have %.3g nonzeros (%.1f "
                    "GB) and cost %.3g flops per iteration (%s ordering), "
                    "more than allowed; conjugate gradients (CGNR, Jacobi)",
                    estimate.nonzeros, estimate.nonzeros * sizeof(double) / 1e9,
                    estimate.flops, estimated_with.c_str());
      summary.linear_solver_reason = text;
      solver_options.linear_solver_type = ceres::CGNR;
      solver_options.preconditioner_type = ceres::JACOBI;
      solver_options.max_linear_solver_iterations =
          options.max_linear_solver_iterations;
      solver_options.linear_solver_ordering.reset();
      summary.ordering = "none (iterative)";
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

  // Pose graphs: when LM rejects its first kRejectionsBeforeProbe steps,
  // stop it there, take plain Gauss-Newton steps, and let LM go on from
  // their result (or start again from the untouched values when
  // Gauss-Newton diverged). Other graphs run as before.
  const bool probe_allowed =
      options.gauss_newton_probe_iterations > 0 &&
      options.solver == SolverKind::kLevenbergMarquardt && !landmarks;
  FirstStepWatcher watcher;
  if (probe_allowed) solver_options.callbacks.push_back(&watcher);
  // The probe's Newton steps need poses (or Euclidean blocks) only.
  bool newton_possible = true;
  for (const auto& [key, node] : graph->nodes()) {
    double* block = node->value.data();
    if (!problem.HasParameterBlock(block)) continue;
    newton_possible =
        newton_possible && NewtonTransports(problem.GetManifold(block));
  }
  watcher.set_newton_midway(options.newton_under_way && newton_possible);

  ceres::Solver::Summary ceres_summary;
  const auto add_times = [&summary](const ceres::Solver::Summary& s) {
    summary.preprocess_seconds += s.preprocessor_time_in_seconds;
    summary.residual_seconds += s.residual_evaluation_time_in_seconds;
    summary.jacobian_seconds += s.jacobian_evaluation_time_in_seconds;
    summary.linear_solver_seconds += s.linear_solver_time_in_seconds;
  };
  {
    const SerialOpenMpScope serial_openmp;
    ceres::Solve(solver_options, &problem, &ceres_summary);
  }
  add_times(ceres_summary);
  int iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
  // The probe, and LM again from its values: up to kMaxProbes times, LM
  // watched for a stall or a linear tail again in between. All of them
  // share options.max_iterations (a caller's budget, such as the laser's
  // incremental solves of 10 iterations, holds for the whole solve).
  bool budget_spent = false;
  for (int probes = 1;
       watcher.first_steps_rejected() || watcher.stalled_midway(); ++probes) {
    if (iterations >= options.max_iterations) {
      budget_spent = true;
      break;
    }
    std::vector<double*> free_blocks;
    for (const auto& [key, node] : graph->nodes()) {
      double* block = node->value.data();
      // Nodes without factors are not in the problem.
      if (problem.HasParameterBlock(block) &&
          !problem.IsParameterBlockConstant(block)) {
        free_blocks.push_back(block);
      }
    }
    std::ostream* log = options.verbose ? progress : nullptr;
    const bool midway = watcher.stalled_midway();
    if (log != nullptr) {
      if (midway) {
        *log << watcher.midway_reason() << ": Newton steps\n";
      } else {
        *log << "LM rejected its first " << watcher.rejections()
             << " steps: plain Gauss-Newton steps\n";
      }
    }
    ProbeResult probe;
    {
      const SerialOpenMpScope serial_openmp;
      probe = GaussNewtonProbe(&problem, free_blocks,
                               std::min(options.gauss_newton_probe_iterations,
                                        options.max_iterations - iterations),
                               options.function_tolerance, midway,
                               options.newton_under_way, log);
    }
    if (log != nullptr) {
      *log << (probe.converged ? "Gauss-Newton converged; LM confirms\n"
               : probe.stalled
                   ? "Gauss-Newton stalled; LM goes on from its best values\n"
               : probe.improved ? "Gauss-Newton lowered the cost; LM goes on\n"
                                : "Gauss-Newton diverged; LM from the start\n");
    }
    summary.gauss_newton_iterations += probe.iterations;
    // Gauss-Newton steps failed from the values LM resumes at: LM starts
    // from Ceres' default radius instead of an (almost) Gauss-Newton step,
    // which it would reject again and again (seven rejections from 1e12).
    // Likewise after Newton steps from LM's values under way (LM had
    // shrunk its radius there).
    if (probe.stalled || midway) {
      solver_options.initial_trust_region_radius = std::min(
          solver_options.initial_trust_region_radius, kRadiusAfterStall);
    }
    watcher.WatchUnderWay();  // Also clears the flags that ended LM.
    if (probes >= kMaxProbes) {
      solver_options.callbacks.erase(
          std::remove(solver_options.callbacks.begin(),
                      solver_options.callbacks.end(), &watcher),
          solver_options.callbacks.end());
    }
    iterations += probe.iterations;
    if (iterations >= options.max_iterations) {
      budget_spent = true;
      break;
    }
    solver_options.max_num_iterations = options.max_iterations - iterations;
    const SerialOpenMpScope serial_openmp;
    ceres::Solve(solver_options, &problem, &ceres_summary);
    add_times(ceres_summary);
    iterations += static_cast<int>(ceres_summary.iterations.size()) - 1;
  }

  summary.iterations = iterations;
  summary.converged =
      !budget_spent && ceres_summary.termination_type == ceres::CONVERGENCE;
  summary.usable = ceres_summary.IsSolutionUsable();
  summary.termination =
      budget_spent ? "Maximum number of iterations reached (LM and the "
                     "probe's steps together): " +
                         std::to_string(iterations)
                   : ceres_summary.message;
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
