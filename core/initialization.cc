#include "core/initialization.h"

#include <algorithm>
#include <cstdio>
#include <deque>
#include <map>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/lie.h"
#include "core/openmp_scope.h"
#include "core/ordering.h"

namespace slam {
namespace {

// The pose part of the graph, indexed 0..n-1 in key order.
struct PoseGraphView {
  bool is_3d = false;
  std::vector<Node*> nodes;
  std::map<Key, int> index;
  struct Edge {
    int a, b;
    const Factor* factor;
  };
  std::vector<Edge> edges;
  std::vector<std::vector<int>> adjacency;  // Edge indices per node.
  std::vector<bool> known;                  // Anchors: never written.
};

bool BuildView(Graph* graph, const std::set<Key>* only, PoseGraphView* view,
               std::string* error) {
  bool has2 = false, has3 = false;
  for (const auto& [id, f] : graph->factors()) {
    has2 = has2 || f.type == FactorType::kBetweenSE2;
    has3 = has3 || f.type == FactorType::kBetweenSE3;
  }
  if (has2 && has3) {
    *error = "the graph mixes SE(2) and SE(3) between factors";
    return false;
  }
  view->is_3d = has3;
  const NodeKind kind = has3 ? NodeKind::kPose3 : NodeKind::kPose2;
  const FactorType type =
      has3 ? FactorType::kBetweenSE3 : FactorType::kBetweenSE2;
  for (const auto& [key, node] : graph->nodes()) {
    if (key.kind != kind) continue;
    view->index[key] = static_cast<int>(view->nodes.size());
    view->nodes.push_back(node.get());
    view->known.push_back(node->fixed ||
                          (only != nullptr && only->count(key) == 0));
  }
  view->adjacency.resize(view->nodes.size());
  for (const auto& [id, f] : graph->factors()) {
    if (f.type != type) continue;
    const int a = view->index.at(f.keys[0]);
    const int b = view->index.at(f.keys[1]);
    if (a == b) continue;
    view->adjacency[a].push_back(static_cast<int>(view->edges.size()));
    view->adjacency[b].push_back(static_cast<int>(view->edges.size()));
    view->edges.push_back({a, b, &f});
  }
  return true;
}

// Sets node `to` from node `from` through edge e.
void Propagate(const PoseGraphView& view, int e, int from) {
  const PoseGraphView::Edge& edge = view.edges[e];
  Node* src = view.nodes[from];
  Node* dst = view.nodes[from == edge.a ? edge.b : edge.a];
  if (view.is_3d) {
    const Pose3 z = MeasurementPose3(*edge.factor);
    const Pose3 x = NodePose3(*src) * (from == edge.a ? z : z.Inverse());
    const std::vector<double> v = Pose3Value(x);
    std::copy(v.begin(), v.end(), dst->value.begin());
  } else {
    const Pose2 z = MeasurementPose2(*edge.factor);
    const Pose2 x = NodePose2(*src) * (from == edge.a ? z : z.Inverse());
    const std::vector<double> v = Pose2Value(x);
    std::copy(v.begin(), v.end(), dst->value.begin());
  }
}

// Marks every node of the connected component of `start` as reached; returns
// the nodes in breadth-first order.
std::vector<int> Component(const PoseGraphView& view, int start,
                           std::vector<bool>* seen) {
  std::vector<int> order = {start};
  (*seen)[start] = true;
  for (size_t k = 0; k < order.size(); ++k) {
    for (int e : view.adjacency[order[k]]) {
      const int v =
          view.edges[e].a == order[k] ? view.edges[e].b : view.edges[e].a;
      if (!(*seen)[v]) {
        (*seen)[v] = true;
        order.push_back(v);
      }
    }
  }
  return order;
}

// Gives every component without a known node one anchor: its first node.
std::vector<bool> Anchors(const PoseGraphView& view) {
  std::vector<bool> anchor = view.known;
  std::vector<bool> seen(view.nodes.size(), false);
  for (size_t i = 0; i < view.nodes.size(); ++i) {
    if (seen[i]) continue;
    const std::vector<int> comp = Component(view, static_cast<int>(i), &seen);
    bool has_anchor = false;
    for (int k : comp) has_anchor = has_anchor || anchor[k];
    if (!has_anchor) anchor[*std::min_element(comp.begin(), comp.end())] = true;
  }
  return anchor;
}

// Breadth-first propagation from the nodes already set.
void BreadthFirst(const PoseGraphView& view, std::vector<bool>* set) {
  std::deque<int> queue;
  for (size_t i = 0; i < view.nodes.size(); ++i) {
    if ((*set)[i]) queue.push_back(static_cast<int>(i));
  }
  while (!queue.empty()) {
    const int u = queue.front();
    queue.pop_front();
    for (int e : view.adjacency[u]) {
      const int v = view.edges[e].a == u ? view.edges[e].b : view.edges[e].a;
      if ((*set)[v]) continue;
      Propagate(view, e, u);
      (*set)[v] = true;
      queue.push_back(v);
    }
  }
}

void Odometry(const PoseGraphView& view, std::vector<bool>* set) {
  // Edge between consecutive ids, looked up per node.
  auto chain_edge = [&](int u, int v) {
    for (int e : view.adjacency[u]) {
      const auto& edge = view.edges[e];
      if ((edge.a == u && edge.b == v) || (edge.a == v && edge.b == u)) {
        return e;
      }
    }
    return -1;
  };
  const int n = static_cast<int>(view.nodes.size());
  for (int k = 1; k < n; ++k) {  // Forward along increasing ids.
    if ((*set)[k] || !(*set)[k - 1]) continue;
    if (view.nodes[k]->key.id != view.nodes[k - 1]->key.id + 1) continue;
    const int e = chain_edge(k - 1, k);
    if (e < 0) continue;
    Propagate(view, e, k - 1);
    (*set)[k] = true;
  }
  for (int k = n - 2; k >= 0; --k) {  // Backward from anchors in the middle.
    if ((*set)[k] || !(*set)[k + 1]) continue;
    if (view.nodes[k + 1]->key.id != view.nodes[k]->key.id + 1) continue;
    const int e = chain_edge(k, k + 1);
    if (e < 0) continue;
    Propagate(view, e, k + 1);
    (*set)[k] = true;
  }
  BreadthFirst(view, set);
}

// Linear least squares over per-node D x M blocks X_k:
//   minimize sum_e |A_a X_a + A_b X_b + C|_W^2  (column-wise, weight W),
// with the `known` blocks held at their given values. The normal equations
// are factored once and solved for all M columns.
template <int D, int M>
struct LinearTerm {
  int a, b;
  Eigen::Matrix<double, D, D> A_a, A_b, W;
  Eigen::Matrix<double, D, M> C;
};

// The normal equations' solver. The unknowns are numbered in a
// fill-reducing order of the node graph (`order`, from CHOLMOD on nodes:
// several times cheaper than ordering the scalar system), so both backends
// keep that order:
//   kSimplicial   Eigen's simplicial LDLT (int indices): on small, sparse
//                 factors it beats CHOLMOD's per-call set-up (measured:
//                 torus3D 0.18 s vs 0.24 s for the whole initialization,
//                 city10000 0.11 s vs 0.21 s).
//   kSupernodal   CHOLMOD's supernodal LL^T with 64-bit indices: dense
//                 factors (many loop closures) run on BLAS kernels, and
//                 factors beyond 2^31 nonzeros, which overflow Eigen's int
//                 indices, still fit.
//   kIterative    conjugate gradients preconditioned by an incomplete
//                 Cholesky factor (int indices: the system itself, not its
//                 factor, must fit), warm-started from the current values.
class NormalEquationsSolver {
 public:
  NormalEquationsSolver(LinearBackend backend, const InitOptions& options)
      : backend_(backend) {
    if (backend_ == LinearBackend::kSupernodal) {
      cholmod_.cholmod().nmethods = 1;
      cholmod_.cholmod().method[0].ordering = CHOLMOD_NATURAL;
    }
    cg_.setTolerance(options.iterative_tolerance);
    cg_.setMaxIterations(options.max_iterative_iterations);
  }
  LinearBackend backend() const { return backend_; }
  int iterations() const { return iterations_; }
  double iterative_error() const { return iterative_error_; }

  // Factors h (full symmetric, scalar unknowns in elimination order); the
  // symbolic analysis of the first call is kept for later calls with the
  // same pattern (the rotation and translation systems share it).
  template <typename Index>
  bool Factorize(const Eigen::SparseMatrix<double, Eigen::ColMajor, Index>& h) {
    if constexpr (std::is_same_v<Index, int>) {
      if (backend_ == LinearBackend::kIterative) {
        cg_.compute(h);
        return cg_.info() == Eigen::Success;
      }
      if (!analyzed_) eigen_.analyzePattern(h);
      analyzed_ = true;
      eigen_.factorize(h);
      return eigen_.info() == Eigen::Success;
    } else {
      // One OpenMP thread for CHOLMOD's supernodal factorization (see
      // core/openmp_scope.h).
      const SerialOpenMpScope serial_openmp;
      if (!analyzed_) cholmod_.analyzePattern(h);
      analyzed_ = true;
      cholmod_.factorize(h);
      return cholmod_.info() == Eigen::Success;
    }
  }
  // guess: the current values (kIterative starts from them).
  bool Solve(const Eigen::MatrixXd& rhs, const Eigen::MatrixXd& guess,
             Eigen::MatrixXd* x) {
    if (backend_ == LinearBackend::kIterative) {
      x->resize(rhs.rows(), rhs.cols());
      for (Eigen::Index c = 0; c < rhs.cols(); ++c) {
        x->col(c) = cg_.solveWithGuess(rhs.col(c), guess.col(c));
        iterations_ += static_cast<int>(cg_.iterations());
        iterative_error_ = std::max(iterative_error_, cg_.error());
        if (cg_.info() != Eigen::Success) return false;
      }
      return x->allFinite();
    }
    if (backend_ == LinearBackend::kSimplicial) {
      *x = eigen_.solve(rhs);
      return eigen_.info() == Eigen::Success && x->allFinite();
    }
    *x = cholmod_.solve(rhs);
    return cholmod_.info() == Eigen::Success && x->allFinite();
  }

 private:
  using LongMatrix =
      Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  LinearBackend backend_;
  bool analyzed_ = false;
  int iterations_ = 0;
  double iterative_error_ = 0.0;
  Eigen::ConjugateGradient<
      Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
      Eigen::IncompleteCholesky<double, Eigen::Lower,
                                Eigen::NaturalOrdering<int>>>
      cg_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                        Eigen::NaturalOrdering<int>>
      eigen_;
  Eigen::CholmodSupernodalLLT<LongMatrix, Eigen::Lower> cholmod_;
};

// Assembles and factors the normal equations of the terms (Index: the
// backend's index type), then solves for the M columns.
template <typename Index, int D, int M>
bool SolveNormalEquations(const std::vector<LinearTerm<D, M>>& terms,
                          const std::vector<bool>& known,
                          const std::vector<int>& col, int num_unknown,
                          std::vector<Eigen::Matrix<double, D, M>>* x,
                          NormalEquationsSolver* solver, std::string* error) {
  using MatD = Eigen::Matrix<double, D, D>;
  std::vector<Eigen::Triplet<double, Index>> triplets;
  triplets.reserve(terms.size() * 4 * D * D);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(D * num_unknown, M);
  Eigen::MatrixXd guess(D * num_unknown, M);
  for (size_t i = 0; i < known.size(); ++i) {
    if (!known[i]) guess.middleRows<D>(col[i]) = (*x)[i];
  }
  for (const LinearTerm<D, M>& t : terms) {
    Eigen::Matrix<double, D, M> c = t.C;
    if (known[t.a]) c += t.A_a * (*x)[t.a];
    if (known[t.b]) c += t.A_b * (*x)[t.b];
    const int idx[2] = {t.a, t.b};
    const MatD* blocks[2] = {&t.A_a, &t.A_b};
    for (int p = 0; p < 2; ++p) {
      if (known[idx[p]]) continue;
      const MatD atw = blocks[p]->transpose() * t.W;
      rhs.middleRows<D>(col[idx[p]]) -= atw * c;
      for (int q = 0; q < 2; ++q) {
        if (known[idx[q]]) continue;
        const MatD h = atw * *blocks[q];
        for (int r = 0; r < D; ++r) {
          for (int s = 0; s < D; ++s) {
            triplets.emplace_back(col[idx[p]] + r, col[idx[q]] + s, h(r, s));
          }
        }
      }
    }
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, Index> h(D * num_unknown,
                                                        D * num_unknown);
  h.setFromTriplets(triplets.begin(), triplets.end());
  std::vector<Eigen::Triplet<double, Index>>().swap(triplets);
  if (!solver->Factorize(h)) {
    *error = "the linear system of the chordal initialization is singular";
    return false;
  }
  Eigen::MatrixXd sol;
  if (!solver->Solve(rhs, guess, &sol)) {
    if (solver->backend() == LinearBackend::kIterative) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "conjugate gradients did not solve the chordal "
                    "initialization's linear system (relative residual %.3g "
                    "after %d iterations)",
                    solver->iterative_error(), solver->iterations());
      *error = text;
      return false;
    }
    *error = "the linear system of the chordal initialization has no solution";
    return false;
  }
  for (size_t i = 0; i < known.size(); ++i) {
    if (!known[i]) (*x)[i] = sol.middleRows<D>(col[i]);
  }
  return true;
}

template <int D, int M>
bool SolveLinear(const std::vector<LinearTerm<D, M>>& terms,
                 const std::vector<bool>& known, const std::vector<int>& order,
                 std::vector<Eigen::Matrix<double, D, M>>* x,
                 NormalEquationsSolver* solver, std::string* error) {
  const int n = static_cast<int>(known.size());
  std::vector<int> col(n, -1);
  int num_unknown = 0;
  for (int i : order) {
    if (!known[i]) col[i] = D * num_unknown++;
  }
  if (num_unknown == 0) return true;
  if (solver->backend() != LinearBackend::kSupernodal) {
    return SolveNormalEquations<int>(terms, known, col, num_unknown, x, solver,
                                     error);
  }
  return SolveNormalEquations<SuiteSparse_long>(terms, known, col, num_unknown,
                                                x, solver, error);
}

// METIS costs a few microseconds per node; when AMD's factorization would
// cost more than about 2000 flops per scalar unknown (a fraction of a second
// per 100k nodes) METIS is tried as well, and the order with fewer flops
// kept: on grid-like and spherical graphs it cuts the flops 2-5 times
// (100k-node grid2d world, 100 x 100 lattice: 5.2x).
constexpr double kTryMetisFlopsPerUnknown = 2000.0;
// Above ~150 flops per factor entry CHOLMOD's supernodal kernels beat the
// simplicial factorization (the optimizer's measure, core/optimizer.cc); above
// 2^27 nonzeros the simplicial one is slow anyway and near Eigen's int limit.
constexpr double kSupernodalFlopsPerEntry = 150.0;
constexpr double kSimplicialMaxNonzeros = 134217728.0;

std::string Gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f GB", bytes / 1e9);
  return text;
}

// Elimination order of the nodes and the backend for D x D blocks, from
// CHOLMOD's symbolic analysis of the node graph. When the factor would not
// fit (options.max_factor_bytes, max_factor_flops): kIterative with
// options.iterative_fallback, else fails with a message giving its size.
bool PlanSolve(const PoseGraphView& view, int dim, const InitOptions& options,
               std::vector<int>* order, LinearBackend* backend,
               std::string* error) {
  const int n = static_cast<int>(view.nodes.size());
  if (options.backend == LinearBackend::kIterative) {
    // No factor: the unknowns in node order, the preconditioner orders its
    // own.
    order->resize(n);
    std::iota(order->begin(), order->end(), 0);
    *backend = LinearBackend::kIterative;
    return true;
  }
  std::vector<std::pair<int, int>> node_edges;
  node_edges.reserve(view.edges.size());
  for (const auto& edge : view.edges) node_edges.emplace_back(edge.a, edge.b);
  OrderingResult ordering;
  if (!FillReducingOrdering(n, node_edges, "amd", &ordering, error)) {
    return false;
  }
  // Scalar factor: D x D blocks per node-level entry.
  const auto excess = [&](const OrderingResult& o) {
    return FactorExcess(o.factor_nonzeros * dim * dim,
                        o.factor_flops * dim * dim * dim,
                        options.max_factor_bytes, options.max_factor_flops);
  };
  const bool hopeless = options.backend == LinearBackend::kAuto &&
                        options.iterative_fallback &&
                        excess(ordering) > kNoOrderingHelps;
  if (!hopeless && ordering.factor_flops * dim * dim >
                       kTryMetisFlopsPerUnknown * static_cast<double>(n)) {
    OrderingResult metis;
    if (!FillReducingOrdering(n, node_edges, "metis", &metis, error)) {
      return false;
    }
    if (metis.factor_flops < ordering.factor_flops) ordering = std::move(metis);
  }
  *order = std::move(ordering.order);
  // Scalar factor: D x D blocks per node-level entry.
  const double nonzeros = ordering.factor_nonzeros * dim * dim;
  const double flops = ordering.factor_flops * dim * dim * dim;
  const double bytes = nonzeros * sizeof(double);
  if (excess(ordering) > 1.0) {
    if (options.backend == LinearBackend::kAuto && options.iterative_fallback) {
      std::iota(order->begin(), order->end(), 0);
      *backend = LinearBackend::kIterative;
      return true;
    }
    const double budget = options.max_factor_bytes > 0.0
                              ? options.max_factor_bytes
                              : 0.5 * PhysicalMemoryBytes();
    char text[320];
    std::snprintf(text, sizeof(text),
                  "the chordal initialization's sparse factor would have "
                  "%.3g nonzeros (%s) and cost %.3g flops (%s ordering of %d "
                  "nodes), more than the %s and %.3g flops allowed (dense "
                  "loop closures fill the factor; the optimizer's own "
                  "factorization would cost even more)",
                  nonzeros, Gigabytes(bytes).c_str(), flops,
                  ordering.method.c_str(), n, Gigabytes(budget).c_str(),
                  options.max_factor_flops);
    *error = text;
    return false;
  }
  if (options.backend != LinearBackend::kAuto) {
    *backend = options.backend;
  } else {
    const double flops_per_entry = nonzeros > 0.0 ? flops / nonzeros : 0.0;
    *backend = flops_per_entry > kSupernodalFlopsPerEntry ||
                       nonzeros > kSimplicialMaxNonzeros
                   ? LinearBackend::kSupernodal
                   : LinearBackend::kSimplicial;
  }
  return true;
}

Eigen::Matrix3d ProjectToSO3(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0
                                                                          : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

// Rotation matrix of a node / of a factor's measurement, 2D or 3D.
template <int D>
Eigen::Matrix<double, D, D> NodeRotation(const Node& node) {
  if constexpr (D == 3) {
    return Eigen::Quaterniond(node.value[6], node.value[3], node.value[4],
                              node.value[5])
        .normalized()
        .toRotationMatrix();
  } else {
    return RotationMatrix2D(node.value[2]);
  }
}

template <int D>
Eigen::Matrix<double, D, D> MeasuredRotation(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  if constexpr (D == 3) {
    return Eigen::Quaterniond(m[6], m[3], m[4], m[5])
        .normalized()
        .toRotationMatrix();
  } else {
    return RotationMatrix2D(m[2]);
  }
}

// 1b. (3D) Gauss-Newton on the rotations alone, from the chordal estimate.
// The chordal relaxation weighs every measurement isotropically (a scalar per
// edge), but real graphs carry anisotropic rotation information (e.g.
// parking-garage: loop closures four times weaker about the vertical), and
// the relaxation over all 3x3 matrices cannot honour it. These iterations
// minimize sum_e |Log(R_z^T R_a^T R_b)|^2 over Omega_theta = Omega_qvec / 4
// (g2o's rotation information is over the quaternion vector part, about half
// the angle) with right perturbations R <- R Exp(delta): the rotation part of
// the pose-graph cost, so the translations solved next start from rotations
// consistent with the information the optimizer will use.
constexpr int kRotationRefinementIterations = 2;

bool RefineRotations(const PoseGraphView& view,
                     const std::vector<Eigen::Matrix3d>& measured,
                     const std::vector<bool>& anchor,
                     const std::vector<int>& order,
                     std::vector<Eigen::Matrix3d>* rot,
                     NormalEquationsSolver* solver, std::string* error) {
  const int n = static_cast<int>(view.nodes.size());
  std::vector<LinearTerm<3, 1>> terms(view.edges.size());
  for (int it = 0; it < kRotationRefinementIterations; ++it) {
    for (size_t e = 0; e < view.edges.size(); ++e) {
      const auto& edge = view.edges[e];
      LinearTerm<3, 1>& t = terms[e];
      t.a = edge.a;
      t.b = edge.b;
      const Eigen::Matrix3d r_ab = (*rot)[edge.a].transpose() * (*rot)[edge.b];
      const Eigen::Vector3d r0 = QuaternionLog<double>(
          Eigen::Quaterniond(measured[e].transpose() * r_ab));
      // Log(R_e Exp(u)) ~ r0 + Jr^-1(r0) u, u = delta_b - R_ab^T delta_a.
      const Eigen::Matrix3d jr_inv = RightJacobianInverseSO3(r0);
      t.A_a = -jr_inv * r_ab.transpose();
      t.A_b = jr_inv;
      const Eigen::Matrix3d info =
          edge.factor->information.bottomRightCorner<3, 3>();
      t.W = 0.125 * (info + info.transpose());
      t.C = r0;
    }
    std::vector<Eigen::Vector3d> delta(n, Eigen::Vector3d::Zero());
    if (!SolveLinear<3, 1>(terms, anchor, order, &delta, solver, error)) {
      return false;
    }
    for (int i = 0; i < n; ++i) {
      if (anchor[i]) continue;
      (*rot)[i] =
          (*rot)[i] * QuaternionExp<double>(delta[i]).toRotationMatrix();
    }
  }
  return true;
}

// 1b. (2D) Gauss-Newton on the headings alone, from the chordal estimate:
// minimize sum_e w_e wrap(theta_b - theta_a - theta_z)^2 (w_e: the heading
// information). The relaxation over unit-free (cos, sin) vectors followed by
// normalization is not this least-squares fit; under heavy heading noise
// (0.1-0.3 rad) the difference is what made LM reject its first steps from
// the chordal start and crawl (a 3500-pose grid world: 106 iterations). The
// problem is linear up to the wrap, so two steps suffice. The system has its
// own (scalar) pattern, hence its own solver.
bool RefineHeadings(const PoseGraphView& view, const std::vector<bool>& anchor,
                    const std::vector<int>& order, LinearBackend backend,
                    const InitOptions& options,
                    std::vector<Eigen::Matrix2d>* rot, std::string* error) {
  const int n = static_cast<int>(view.nodes.size());
  std::vector<double> theta(n);
  for (int i = 0; i < n; ++i) {
    theta[i] = std::atan2((*rot)[i](1, 0), (*rot)[i](0, 0));
  }
  NormalEquationsSolver solver(backend, options);
  std::vector<LinearTerm<1, 1>> terms(view.edges.size());
  for (int it = 0; it < kRotationRefinementIterations; ++it) {
    for (size_t e = 0; e < view.edges.size(); ++e) {
      const auto& edge = view.edges[e];
      LinearTerm<1, 1>& t = terms[e];
      t.a = edge.a;
      t.b = edge.b;
      t.A_a(0, 0) = -1.0;
      t.A_b(0, 0) = 1.0;
      t.W(0, 0) = std::max(edge.factor->information(2, 2), 1e-12);
      t.C(0, 0) = NormalizeAngle(theta[edge.b] - theta[edge.a] -
                                 edge.factor->measurement(2));
    }
    std::vector<Eigen::Matrix<double, 1, 1>> delta(
        n, Eigen::Matrix<double, 1, 1>::Zero());
    if (!SolveLinear<1, 1>(terms, anchor, order, &delta, &solver, error)) {
      return false;
    }
    for (int i = 0; i < n; ++i) {
      if (!anchor[i]) theta[i] += delta[i](0, 0);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!anchor[i]) (*rot)[i] = RotationMatrix2D(NormalizeAngle(theta[i]));
  }
  return true;
}

// D = 2 or 3. Rotation unknowns: 2D X_k = (cos, sin), the first column of
// R_k, with constraint X_b - R_z X_a = 0 (M = 1); 3D X_k = R_k^T, with
// constraint R_z^T X_a - X_b = 0 (M = 3, one column per row of R_k).
template <int D>
bool ChordalImpl(const PoseGraphView& view, const std::vector<bool>& anchor,
                 const InitOptions& options, std::string* error,
                 InitReport* report) {
  constexpr int M = D == 3 ? 3 : 1;
  using MatD = Eigen::Matrix<double, D, D>;
  using VecD = Eigen::Matrix<double, D, 1>;
  const int n = static_cast<int>(view.nodes.size());
  // 1. Rotations, weighted isotropically by the rotation information.
  std::vector<Eigen::Matrix<double, D, M>> x(n);
  for (int i = 0; i < n; ++i) {
    const MatD r = NodeRotation<D>(*view.nodes[i]);
    if constexpr (D == 3) {
      x[i] = r.transpose();
    } else {
      x[i] = r.col(0);
    }
  }
  std::vector<LinearTerm<D, M>> terms(view.edges.size());
  std::vector<MatD> measured(view.edges.size());
  for (size_t e = 0; e < view.edges.size(); ++e) {
    const auto& edge = view.edges[e];
    LinearTerm<D, M>& t = terms[e];
    t.a = edge.a;
    t.b = edge.b;
    measured[e] = MeasuredRotation<D>(*edge.factor);
    const Eigen::MatrixXd& info = edge.factor->information;
    double w;
    if constexpr (D == 3) {
      t.A_a = measured[e].transpose();
      t.A_b = -MatD::Identity();
      w = info.bottomRightCorner<3, 3>().trace() / 3.0;
    } else {
      t.A_a = -measured[e];
      t.A_b = MatD::Identity();
      w = info(2, 2);
    }
    t.W = MatD::Identity() * std::max(w, 1e-12);
    t.C.setZero();
  }
  std::vector<int> order;
  LinearBackend backend;
  if (!PlanSolve(view, D, options, &order, &backend, error)) return false;
  NormalEquationsSolver solver(backend, options);
  report->backend = backend;
  const auto record = [&] {
    report->iterative_iterations = solver.iterations();
    report->iterative_error = solver.iterative_error();
  };
  if (!SolveLinear<D, M>(terms, anchor, order, &x, &solver, error)) {
    record();
    return false;
  }
  std::vector<MatD> rot(n);
  for (int i = 0; i < n; ++i) {
    if (anchor[i]) {
      rot[i] = NodeRotation<D>(*view.nodes[i]);
    } else if constexpr (D == 3) {
      rot[i] = ProjectToSO3(x[i].transpose());
    } else {
      rot[i] = RotationMatrix2D(std::atan2(x[i](1, 0), x[i](0, 0)));
    }
  }
  if constexpr (D == 3) {
    if (!RefineRotations(view, measured, anchor, order, &rot, &solver, error)) {
      record();
      return false;
    }
  } else {
    if (!RefineHeadings(view, anchor, order, backend, options, &rot, error)) {
      record();
      return false;
    }
  }
  // 2. Translations with rotations fixed: t_b - t_a - R_a t_z = 0. The error
  // t_E = (R_a R_z)^T (t_b - t_a - R_a t_z) lives in the frame of X_a Z, so
  // the translation information is rotated by R_a R_z into the world.
  std::vector<Eigen::Matrix<double, D, 1>> t(n);
  for (int i = 0; i < n; ++i) {
    t[i] = Eigen::Map<const VecD>(view.nodes[i]->value.data());
  }
  std::vector<LinearTerm<D, 1>> tterms(view.edges.size());
  for (size_t e = 0; e < view.edges.size(); ++e) {
    const auto& edge = view.edges[e];
    LinearTerm<D, 1>& term = tterms[e];
    term.a = edge.a;
    term.b = edge.b;
    term.A_a = -MatD::Identity();
    term.A_b = MatD::Identity();
    const MatD info_t = edge.factor->information.topLeftCorner<D, D>();
    const MatD& ra = rot[edge.a];
    const MatD raz = ra * measured[e];
    term.W = raz * info_t * raz.transpose();
    term.C = -ra * edge.factor->measurement.head<D>();
  }
  const bool solved =
      SolveLinear<D, 1>(tterms, anchor, order, &t, &solver, error);
  record();
  if (!solved) return false;
  for (int i = 0; i < n; ++i) {
    if (anchor[i]) continue;
    if constexpr (D == 3) {
      const Eigen::Quaterniond q(rot[i]);
      const double v[7] = {t[i].x(), t[i].y(), t[i].z(), q.x(),
                           q.y(),    q.z(),    q.w()};
      std::copy(v, v + 7, view.nodes[i]->value.begin());
    } else {
      const double v[3] = {t[i].x(), t[i].y(),
                           std::atan2(rot[i](1, 0), rot[i](0, 0))};
      std::copy(v, v + 3, view.nodes[i]->value.begin());
    }
  }
  return true;
}

bool Chordal(const PoseGraphView& view, const std::vector<bool>& anchor,
             const InitOptions& options, std::string* error,
             InitReport* report) {
  return view.is_3d ? ChordalImpl<3>(view, anchor, options, error, report)
                    : ChordalImpl<2>(view, anchor, options, error, report);
}

}  // namespace

const char* InitMethodName(InitMethod method) {
  switch (method) {
    case InitMethod::kNone:
      return "none";
    case InitMethod::kOdometry:
      return "odometry";
    case InitMethod::kSpanningTree:
      return "spanning_tree";
    case InitMethod::kChordal:
      return "chordal";
  }
  return "none";
}

bool ParseInitMethod(const std::string& text, InitMethod* method) {
  for (InitMethod m : {InitMethod::kNone, InitMethod::kOdometry,
                       InitMethod::kSpanningTree, InitMethod::kChordal}) {
    if (text == InitMethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

const char* LinearBackendName(LinearBackend backend) {
  switch (backend) {
    case LinearBackend::kAuto:
      return "auto";
    case LinearBackend::kSimplicial:
      return "simplicial LDLT";
    case LinearBackend::kSupernodal:
      return "supernodal Cholesky";
    case LinearBackend::kIterative:
      return "conjugate gradients";
  }
  return "auto";
}

bool InitializePoses(Graph* graph, InitMethod method, std::string* error,
                     const std::set<Key>* only, const InitOptions& options,
                     InitReport* report) {
  InitReport unused;
  if (report == nullptr) report = &unused;
  if (method == InitMethod::kNone) return true;
  PoseGraphView view;
  if (!BuildView(graph, only, &view, error)) return false;
  if (view.nodes.empty()) return true;
  std::vector<bool> anchor = Anchors(view);
  switch (method) {
    case InitMethod::kOdometry:
      Odometry(view, &anchor);
      return true;
    case InitMethod::kSpanningTree:
      BreadthFirst(view, &anchor);
      return true;
    case InitMethod::kChordal:
      return Chordal(view, anchor, options, error, report);
    case InitMethod::kNone:
      break;
  }
  return true;
}

}  // namespace slam
