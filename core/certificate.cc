#include "core/certificate.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>

#include <Spectra/SymEigsShiftSolver.h>
#include <amd.h>
#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>

#include "ceres/ceres.h"
#include "core/lie.h"
#include "core/openmp_scope.h"

namespace slam {
namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// Adds the time since the previous lap to a named phase (no-op without a
// map).
class PhaseClock {
 public:
  explicit PhaseClock(std::map<std::string, double>* phases)
      : phases_(phases), last_(std::chrono::steady_clock::now()) {}
  void Lap(const char* name) {
    if (phases_ == nullptr) return;
    const auto now = std::chrono::steady_clock::now();
    (*phases_)[name] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  std::map<std::string, double>* phases_;
  std::chrono::steady_clock::time_point last_;
};

// The nearest rotation (SO(d)) to a square matrix.
Eigen::MatrixXd ProjectToRotation(const Eigen::MatrixXd& m) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::MatrixXd u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0) {
    u.col(u.cols() - 1) *= -1.0;
  }
  return u * svd.matrixV().transpose();
}

// The nearest matrix with orthonormal columns (Stiefel manifold).
Eigen::MatrixXd ProjectToStiefel(const Eigen::MatrixXd& m) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(
      m, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return svd.matrixU() * svd.matrixV().transpose();
}

// A rotation of SO(r) whose first d columns are the orthonormal columns of
// y (r x d): y's complement from a QR factorization, sign fixed for det +1.
Eigen::MatrixXd CompleteToRotation(const Eigen::MatrixXd& y) {
  const int r = y.rows(), d = y.cols();
  Eigen::MatrixXd full(r, r);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(y);
  full = qr.householderQ() * Eigen::MatrixXd::Identity(r, r);
  full.leftCols(d) = y;
  if (r > d && full.determinant() < 0) full.col(r - 1) *= -1.0;
  return full;
}

// SO(r) stored as a column-major r x r matrix; tangent: skew-symmetric
// matrices in the basis G_k = E_ab - E_ba (a < b); Plus by the Cayley
// transform X (I - A/2)^-1 (I + A/2). For r = d + 1 its first d columns
// parametrize the Stiefel manifold St(d, r) one to one (same dimension);
// for r > d + 1 the extra directions only turn the unused columns (LM's
// damping keeps them bounded).
class RotationMatrixManifold final : public ceres::Manifold {
 public:
  explicit RotationMatrixManifold(int r) : r_(r) {
    for (int a = 0; a < r; ++a) {
      for (int b = a + 1; b < r; ++b) pairs_.emplace_back(a, b);
    }
  }
  int AmbientSize() const override { return r_ * r_; }
  int TangentSize() const override { return static_cast<int>(pairs_.size()); }

  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override {
    Eigen::Map<const Eigen::MatrixXd> xm(x, r_, r_);
    const Eigen::MatrixXd a = Hat(delta);
    const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(r_, r_);
    const Eigen::MatrixXd cayley =
        (eye - 0.5 * a).partialPivLu().solve(eye + 0.5 * a);
    Eigen::Map<Eigen::MatrixXd>(x_plus_delta, r_, r_) = xm * cayley;
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<const Eigen::MatrixXd> xm(x, r_, r_);
    const int t = TangentSize();
    Eigen::Map<
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        jac(jacobian, r_ * r_, t);
    jac.setZero();
    // d(X G_k) with G_k = E_ab - E_ba: column b gets X.col(a), column a
    // gets -X.col(b).
    for (int k = 0; k < t; ++k) {
      const auto [a, b] = pairs_[k];
      for (int c = 0; c < r_; ++c) {
        jac(c + r_ * b, k) += xm(c, a);
        jac(c + r_ * a, k) -= xm(c, b);
      }
    }
    return true;
  }
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override {
    Eigen::Map<const Eigen::MatrixXd> xm(x, r_, r_), ym(y, r_, r_);
    const Eigen::MatrixXd m = xm.transpose() * ym;
    const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(r_, r_);
    // Inverse Cayley: A = 2 (M - I)(M + I)^-1.
    const Eigen::MatrixXd a = 2.0 * (m + eye)
                                        .transpose()
                                        .partialPivLu()
                                        .solve((m - eye).transpose())
                                        .transpose();
    for (size_t k = 0; k < pairs_.size(); ++k) {
      const auto [p, q] = pairs_[k];
      y_minus_x[k] = 0.5 * (a(p, q) - a(q, p));
    }
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<const Eigen::MatrixXd> xm(x, r_, r_);
    const int t = TangentSize();
    Eigen::Map<
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        jac(jacobian, t, r_ * r_);
    jac.setZero();
    for (int k = 0; k < t; ++k) {
      const auto [a, b] = pairs_[k];
      for (int c = 0; c < r_; ++c) {
        jac(k, c + r_ * b) += 0.5 * xm(c, a);
        jac(k, c + r_ * a) -= 0.5 * xm(c, b);
      }
    }
    return true;
  }

 private:
  Eigen::MatrixXd Hat(const double* delta) const {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(r_, r_);
    for (size_t k = 0; k < pairs_.size(); ++k) {
      const auto [p, q] = pairs_[k];
      a(p, q) = delta[k];
      a(q, p) = -delta[k];
    }
    return a;
  }
  int r_;
  std::vector<std::pair<int, int>> pairs_;
};

// One edge of f at rank r: residuals sqrt(kappa) (Y_j - Y_i Rm) (r x d,
// column-major) and sqrt(tau) (t_j - t_i - Y_i tm) (r), where Y_i is the
// first d columns of the SO(r) block. Linear in the ambient parameters.
// Parameter blocks: Q_i (r*r), Q_j (r*r), t_i (r), t_j (r).
class IsotropicEdgeCost final : public ceres::CostFunction {
 public:
  IsotropicEdgeCost(int r, const IsotropicEdge& e)
      : r_(r),
        d_(e.R.rows()),
        sk_(std::sqrt(e.w.kappa)),
        st_(std::sqrt(e.w.tau)),
        rm_(e.R),
        tm_(e.t) {
    set_num_residuals(r * d_ + r);
    *mutable_parameter_block_sizes() = {r * r, r * r, r, r};
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int r = r_, d = d_;
    Eigen::Map<const Eigen::MatrixXd> qi(parameters[0], r, r);
    Eigen::Map<const Eigen::MatrixXd> qj(parameters[1], r, r);
    Eigen::Map<const Eigen::VectorXd> ti(parameters[2], r);
    Eigen::Map<const Eigen::VectorXd> tj(parameters[3], r);
    Eigen::Map<Eigen::MatrixXd> rot(residuals, r, d);
    Eigen::Map<Eigen::VectorXd> tra(residuals + r * d, r);
    rot = sk_ * (qj.leftCols(d) - qi.leftCols(d) * rm_);
    tra = st_ * (tj - ti - qi.leftCols(d) * tm_);
    if (jacobians == nullptr) return true;
    const int rows = r * d + r;
    using RowMajor =
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    if (jacobians[0] != nullptr) {
      Eigen::Map<RowMajor> jac(jacobians[0], rows, r * r);
      jac.setZero();
      for (int a = 0; a < r; ++a) {
        for (int b = 0; b < d; ++b) {
          for (int c = 0; c < d; ++c) {
            jac(a + r * c, a + r * b) = -sk_ * rm_(b, c);
          }
          jac(r * d + a, a + r * b) = -st_ * tm_(b);
        }
      }
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<RowMajor> jac(jacobians[1], rows, r * r);
      jac.setZero();
      for (int a = 0; a < r; ++a) {
        for (int c = 0; c < d; ++c) jac(a + r * c, a + r * c) = sk_;
      }
    }
    for (int k = 2; k < 4; ++k) {
      if (jacobians[k] == nullptr) continue;
      Eigen::Map<RowMajor> jac(jacobians[k], rows, r);
      jac.setZero();
      for (int a = 0; a < r; ++a) jac(r * d + a, a) = k == 2 ? -st_ : st_;
    }
    return true;
  }

 private:
  int r_, d_;
  double sk_, st_;
  Eigen::MatrixXd rm_;
  Eigen::VectorXd tm_;
};

// The blocks of M with node 0's translation grounded (dropped): translations
// of nodes 1..n-1 (n-1), rotations (d n).
struct ReducedBlocks {
  int n = 0, d = 0;
  SpMat tt, tr, rr;  // M_tt (n-1)^2, M_tR (n-1) x dn, M_RR dn x dn.
  // Fill-reducing elimination order of the nodes, shared by every sparse
  // factorization of the certificate: SuiteSparse's AMD on the translation
  // Laplacian's pattern (the pose graph without node 0), node 0 last.
  // position[i] is node i's place in it.
  std::vector<int> position;
  // M_tt permuted to that order (tt_order: node i - 1 -> position[i]).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> tt_order;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::NaturalOrdering<int>>
      tt_factor;
};

// Scalar permutations (old index -> new) that put the unknowns of the
// Newton Hessian (per node 1..n-1: block scalars) and of K (translations
// of nodes 1..n-1, then d rotation scalars per node) node by node in the
// order of b.position, so that the factorizations need no ordering of
// their own (the orderings of the scalar matrices were 10-30 % of a 2D
// graph's certificate: two minimum-degree runs on 3n unknowns).
std::vector<int> HessianPermutation(const ReducedBlocks& b, int block) {
  std::vector<int> perm(static_cast<size_t>(block) * (b.n - 1));
  for (int i = 1; i < b.n; ++i) {
    for (int a = 0; a < block; ++a) {
      perm[block * (i - 1) + a] = block * b.position[i] + a;
    }
  }
  return perm;
}
std::vector<int> CertificatePermutation(const ReducedBlocks& b) {
  const int n = b.n, d = b.d, nt = n - 1;
  std::vector<int> perm(static_cast<size_t>(nt) + d * n);
  for (int i = 0; i < n; ++i) {
    const int offset = (1 + d) * b.position[i];
    if (i > 0) perm[i - 1] = offset;
    for (int a = 0; a < d; ++a) perm[nt + d * i + a] = offset + (i > 0) + a;
  }
  return perm;
}

// The elimination order of the pose graph (its Laplacian, both triangles,
// in `laplacian`; AMD's order given): METIS's nested dissection instead
// when it needs fewer flops by CHOLMOD's symbolic count for the Laplacian
// (the node-blocked factorizations scale with it: blocks of b unknowns
// multiply every column count by b, the flops by b^3). Tried only on 3D
// graphs whose Newton Hessian (blocks of 6) would have dense fronts by
// AMD's count (supernodal_flops_per_entry, as PositiveDefiniteFactor
// decides): METIS costs more than AMD (sphere2500 16 ms, city10000 117 ms
// against a few), which pays only where the factorizations dominate.
// Nested dissection wins there (sphere2500's Newton Hessian 3.57e8 flops
// against 3.97e8, K 1.06e8 against 1.18e8; torus3D 9.8e8 against 1.35e9),
// AMD elsewhere (parking-garage 3.0e7 against 2.2e7; on the 2D graphs
// 1.03-1.31 times AMD's count but city10000's 0.87).
void ChooseNodeOrdering(SpMat* laplacian, int d,
                        const CertificateOptions& options,
                        std::vector<int>* order) {
  using Ordering = CertificateOptions::Ordering;
  const int size = static_cast<int>(laplacian->rows());
  if (size < 2 || options.ordering == Ordering::kAmd) return;
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.supernodal = CHOLMOD_SIMPLICIAL;  // Counts only.
  cholmod_sparse a = Eigen::viewAsCholmod(*laplacian);
  a.stype = 1;  // Symmetric, its upper triangle read.
  // CHOLMOD's flops for the given order (0 when it fails).
  auto flops = [&](std::vector<int>* perm, double* entries) {
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 0;
    cholmod_factor* f = cholmod_analyze_p(&a, perm->data(), nullptr, 0, &c);
    const bool ok = f != nullptr && c.status == CHOLMOD_OK;
    cholmod_free_factor(&f, &c);
    if (entries != nullptr) *entries = ok ? c.lnz : 0.0;
    return ok ? c.fl : 0.0;
  };
  constexpr int kBlock = 6;  // The 3D Newton Hessian's.
  double amd_entries = 0.0;
  const double amd_flops = options.ordering == Ordering::kAuto && d == 3
                               ? flops(order, &amd_entries)
                               : 0.0;
  const bool dense =
      amd_entries > 0.0 &&
      kBlock * amd_flops >= options.supernodal_flops_per_entry * amd_entries;
  if (options.ordering == Ordering::kNestedDissection || dense) {
    std::vector<int> metis(size);
    if (cholmod_metis(&a, nullptr, 0, 0, metis.data(), &c) &&
        c.status == CHOLMOD_OK) {
      const double metis_flops =
          options.ordering == Ordering::kAuto ? flops(&metis, nullptr) : 0.0;
      if (metis_flops > 0.0 ? metis_flops < amd_flops
                            : options.ordering != Ordering::kAuto) {
        order->swap(metis);
      }
    }
  }
  cholmod_finish(&c);
}

bool SplitDataMatrix(const SpMat& m, int n, int d,
                     const CertificateOptions& options, ReducedBlocks* blocks,
                     std::string* error) {
  blocks->n = n;
  blocks->d = d;
  Triplets tt, tr, rr;
  for (int k = 0; k < m.outerSize(); ++k) {
    for (SpMat::InnerIterator it(m, k); it; ++it) {
      const int row = it.row(), col = it.col();
      if (row == 0 || col == 0) continue;  // Grounded translation.
      if (row < n && col < n) {
        tt.emplace_back(row - 1, col - 1, it.value());
      } else if (row < n) {
        tr.emplace_back(row - 1, col - n, it.value());
      } else if (col >= n) {
        rr.emplace_back(row - n, col - n, it.value());
      }
    }
  }
  blocks->tt.resize(n - 1, n - 1);
  blocks->tt.setFromTriplets(tt.begin(), tt.end());
  blocks->tr.resize(n - 1, d * n);
  blocks->tr.setFromTriplets(tr.begin(), tr.end());
  blocks->rr.resize(d * n, d * n);
  blocks->rr.setFromTriplets(rr.begin(), rr.end());
  // SuiteSparse's AMD on the pose graph (the Laplacian's pattern): as good
  // as CHOLMOD's own AMD on the scalar matrices (sphere2500's Newton factor
  // 3.98e8 flops against 3.97e8; Eigen's AMD on the pose graph 5.6e8).
  std::vector<int> order(n - 1);
  if (amd_order(n - 1, blocks->tt.outerIndexPtr(), blocks->tt.innerIndexPtr(),
                order.data(), nullptr, nullptr) < AMD_OK) {
    *error = "no elimination order for the pose graph";
    return false;
  }
  ChooseNodeOrdering(&blocks->tt, d, options, &order);
  blocks->position.assign(n, n - 1);
  for (int k = 0; k < n - 1; ++k) blocks->position[order[k] + 1] = k;
  blocks->tt_order.resize(n - 1);
  for (int i = 1; i < n; ++i) {
    blocks->tt_order.indices()[i - 1] = blocks->position[i];
  }
  SpMat permuted(n - 1, n - 1);  // Lower triangle, as tt_factor reads it.
  permuted.selfadjointView<Eigen::Lower>() =
      blocks->tt.selfadjointView<Eigen::Lower>().twistedBy(blocks->tt_order);
  blocks->tt_factor.compute(permuted);
  if (blocks->tt_factor.info() != Eigen::Success) {
    *error = "the translation Laplacian cannot be factorized";
    return false;
  }
  return true;
}

// Optimal translations (r x n, t_0 = 0) for rotations y (r x d n).
Eigen::MatrixXd OptimalTranslations(const ReducedBlocks& b,
                                    const Eigen::MatrixXd& y) {
  const Eigen::MatrixXd rest =
      -(b.tt_order.transpose() *
        b.tt_factor.solve(b.tt_order * Eigen::MatrixXd(b.tr * y.transpose())));
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(y.rows(), b.n);
  t.rightCols(b.n - 1) = rest.transpose();
  return t;
}

// Q y^T (d n x r).
Eigen::MatrixXd QTimes(const ReducedBlocks& b, const Eigen::MatrixXd& y) {
  const Eigen::MatrixXd t = OptimalTranslations(b, y);
  return b.rr * y.transpose() +
         b.tr.transpose() * t.rightCols(b.n - 1).transpose();
}

double ReducedObjective(const ReducedBlocks& b, const Eigen::MatrixXd& y) {
  return (y.transpose().array() * QTimes(b, y).array()).sum();
}

// Lambda blocks: sym(Z_i Y_i), Z = Q Y^T.
std::vector<Eigen::MatrixXd> LambdaBlocks(const ReducedBlocks& b,
                                          const Eigen::MatrixXd& y) {
  const Eigen::MatrixXd z = QTimes(b, y);
  std::vector<Eigen::MatrixXd> lambda(b.n);
  for (int i = 0; i < b.n; ++i) {
    const Eigen::MatrixXd zy =
        z.middleRows(b.d * i, b.d) * y.middleCols(b.d * i, b.d);
    lambda[i] = 0.5 * (zy + zy.transpose());
  }
  return lambda;
}

// Sparse Cholesky factorization of a matrix that may fail to be positive
// definite (then Factorize returns false). The matrix comes in a
// fill-reducing order already (assembled node by node in the order of
// ReducedBlocks::position): no ordering here; only its lower triangle is
// read. CHOLMOD's symbolic analysis counts the factor's flops per entry;
// from CertificateOptions::supernodal_flops_per_entry its supernodal
// factorization (dense fronts: sphere2500's certificate matrix 0.09 s
// against 0.24 s with the simplicial one, on ATLAS), else Eigen's
// simplicial one (parking-garage's Newton Hessian, 52 flops per entry, and
// the sparse 2D graphs, whose CHOLMOD analysis costs 1-2 ms). The symbolic
// analysis is done once per pattern (Analyze).
class PositiveDefiniteFactor {
 public:
  explicit PositiveDefiniteFactor(double supernodal_flops_per_entry)
      : flops_per_entry_(supernodal_flops_per_entry) {
    supernodal_llt_.cholmod().print = 0;  // Not positive definite: answer.
    // The matrices come in a fill-reducing order already (NodeOrder).
    supernodal_llt_.cholmod().nmethods = 1;
    supernodal_llt_.cholmod().method[0].ordering = CHOLMOD_NATURAL;
  }
  void Analyze(const SpMat& a) {
    supernodal_llt_.analyzePattern(a);
    // cholmod_analyze's counts for the order used: flops and nnz(L).
    const cholmod_common& c = supernodal_llt_.cholmod();
    supernodal_ = c.lnz > 0 && c.fl >= flops_per_entry_ * c.lnz;
    flops_ = c.fl;
    entries_ = c.lnz;
    if (!supernodal_) simplicial_llt_.analyzePattern(a);
  }
  bool Factorize(const SpMat& a) {
    if (supernodal_) {
      supernodal_llt_.factorize(a);
      return supernodal_llt_.info() == Eigen::Success;
    }
    simplicial_llt_.factorize(a);
    return simplicial_llt_.info() == Eigen::Success;
  }
  // Of the analysed pattern: its flop count and the entries of L (a solve
  // with the factor costs 4 flops per entry).
  double Flops() const { return flops_; }
  double Entries() const { return entries_; }
  Eigen::VectorXd Solve(const Eigen::VectorXd& rhs) const {
    if (supernodal_) return supernodal_llt_.solve(rhs);
    return simplicial_llt_.solve(rhs);
  }

 private:
  double flops_per_entry_;
  bool supernodal_ = false;
  double flops_ = 0.0, entries_ = 0.0;
  Eigen::CholmodSupernodalLLT<SpMat> supernodal_llt_;
  Eigen::SimplicialLLT<SpMat, Eigen::Lower, Eigen::NaturalOrdering<int>>
      simplicial_llt_;
};

// K(sigma) = [M_tt M_tR; M_Rt M_RR - Lambda - sigma I] (lower triangle),
// factorized by LDL^T; its inertia is M_tt's (positive) plus S - sigma I's.
class ShiftedCertificateOp {
 public:
  using Scalar = double;
  ShiftedCertificateOp(const ReducedBlocks& b,
                       const std::vector<Eigen::MatrixXd>& lambda,
                       double supernodal_flops_per_entry,
                       std::map<std::string, double>* phases)
      : b_(b),
        lambda_(lambda),
        llt_(supernodal_flops_per_entry),
        phases_(phases),
        perm_(CertificatePermutation(b)) {}
  Eigen::Index rows() const { return b_.d * b_.n; }
  Eigen::Index cols() const { return rows(); }
  void set_shift(double sigma) {
    if (factorizations_ > 0 && sigma == shift_) return;  // Spectra's call.
    shift_ = sigma;
    PhaseClock clock(phases_);
    const int nt = b_.n - 1, d = b_.d;
    Triplets triplets;
    triplets.reserve(b_.tt.nonZeros() + 2 * b_.tr.nonZeros() +
                     b_.rr.nonZeros() + d * d * b_.n + d * b_.n);
    const std::vector<int>& p = perm_;
    for (int k = 0; k < b_.tt.outerSize(); ++k) {
      for (SpMat::InnerIterator it(b_.tt, k); it; ++it) {
        triplets.emplace_back(p[it.row()], p[it.col()], it.value());
      }
    }
    for (int k = 0; k < b_.tr.outerSize(); ++k) {
      for (SpMat::InnerIterator it(b_.tr, k); it; ++it) {
        triplets.emplace_back(p[it.row()], p[nt + it.col()], it.value());
        triplets.emplace_back(p[nt + it.col()], p[it.row()], it.value());
      }
    }
    for (int k = 0; k < b_.rr.outerSize(); ++k) {
      for (SpMat::InnerIterator it(b_.rr, k); it; ++it) {
        triplets.emplace_back(p[nt + it.row()], p[nt + it.col()], it.value());
      }
    }
    for (int i = 0; i < b_.n; ++i) {
      for (int a = 0; a < d; ++a) {
        for (int c = 0; c < d; ++c) {
          triplets.emplace_back(p[nt + d * i + a], p[nt + d * i + c],
                                -lambda_[i](a, c) - (a == c ? sigma : 0.0));
        }
      }
    }
    SpMat k(nt + d * b_.n, nt + d * b_.n);
    k.setFromTriplets(triplets.begin(), triplets.end());
    ++factorizations_;
    // A Cholesky factor exists iff K(sigma) > 0, i.e. S > sigma I (the
    // usual case: certified, or sigma below lambda_min). Else LDL^T counts
    // the negative pivots. The pattern does not depend on sigma.
    clock.Lap("k_assemble");
    if (factorizations_ == 1) llt_.Analyze(k);
    clock.Lap("k_analyze");
    llt_ok_ = llt_.Factorize(k);
    clock.Lap("k_factorize");
    if (llt_ok_) return;
    factor_.compute(k);
    clock.Lap("k_ldlt");
  }
  bool ok() const { return llt_ok_ || factor_.info() == Eigen::Success; }
  int NegativePivots() const {
    if (llt_ok_) return 0;
    return static_cast<int>((factor_.vectorD().array() < 0.0).count());
  }
  void perform_op(const double* x_in, double* y_out) const {
    const int nt = b_.n - 1;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nt + rows());
    for (int k = 0; k < rows(); ++k) rhs(perm_[nt + k]) = x_in[k];
    Eigen::VectorXd sol;
    if (llt_ok_) {
      sol = llt_.Solve(rhs);
    } else {
      sol = factor_.solve(rhs);
    }
    for (int k = 0; k < rows(); ++k) y_out[k] = sol(perm_[nt + k]);
  }
  int factorizations() const { return factorizations_; }

 private:
  const ReducedBlocks& b_;
  const std::vector<Eigen::MatrixXd>& lambda_;
  Eigen::SimplicialLDLT<SpMat> factor_;
  PositiveDefiniteFactor llt_;
  std::map<std::string, double>* phases_;
  std::vector<int> perm_;  // CertificatePermutation.
  bool llt_ok_ = false;
  double shift_ = 0.0;
  int factorizations_ = 0;
};

std::vector<int> ParentInit(int n) {
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  return parent;
}
int Root(std::vector<int>* parent, int i) {
  while ((*parent)[i] != i) i = (*parent)[i] = (*parent)[(*parent)[i]];
  return i;
}

}  // namespace

bool IsotropicWeightsFromInformation(const Eigen::MatrixXd& information,
                                     int dim, IsotropicWeights* weights) {
  const int size = dim == 2 ? 3 : 6;
  if ((dim != 2 && dim != 3) || information.rows() != size ||
      information.cols() != size) {
    return false;
  }
  const Eigen::MatrixXd trans = information.topLeftCorner(dim, dim);
  Eigen::LLT<Eigen::MatrixXd> llt_t(trans);
  if (llt_t.info() != Eigen::Success) return false;
  weights->tau = dim / llt_t.solve(Eigen::MatrixXd::Identity(dim, dim)).trace();
  if (dim == 2) {
    weights->kappa = information(2, 2);
    return weights->kappa > 0.0;
  }
  const Eigen::MatrixXd rot = information.bottomRightCorner(3, 3);
  Eigen::LLT<Eigen::MatrixXd> llt_r(rot);
  if (llt_r.info() != Eigen::Success) return false;
  weights->kappa =
      3.0 / (2.0 * llt_r.solve(Eigen::MatrixXd::Identity(3, 3)).trace());
  return true;
}

bool BuildIsotropicProblem(const Graph& graph, IsotropicProblem* problem,
                           std::string* error) {
  *problem = IsotropicProblem();
  std::map<Key, int> index;
  int fixed = 0;
  for (const auto& [key, node] : graph.nodes()) {
    const int d = key.kind == NodeKind::kPose2   ? 2
                  : key.kind == NodeKind::kPose3 ? 3
                                                 : 0;
    if (d == 0 || (problem->d != 0 && d != problem->d)) {
      *error =
          "the certificate needs a pose graph of SE(2) or of SE(3) "
          "nodes only";
      return false;
    }
    problem->d = d;
    fixed += node->fixed;
    index[key] = static_cast<int>(problem->nodes.size());
    problem->nodes.push_back(key);
  }
  if (problem->nodes.size() < 2) {
    *error = "the certificate needs at least two poses";
    return false;
  }
  if (fixed > 1) {
    *error = "the certificate needs at most one fixed node (the gauge)";
    return false;
  }
  const int d = problem->d;
  const int n = static_cast<int>(problem->nodes.size());
  std::vector<int> parent = ParentInit(n);
  for (const auto& [id, factor] : graph.factors()) {
    const bool between2 = factor.type == FactorType::kBetweenSE2 && d == 2;
    const bool between3 = factor.type == FactorType::kBetweenSE3 && d == 3;
    if (!between2 && !between3) {
      *error = std::string(
                   "the certificate covers relative-pose factors "
                   "only, not ") +
               FactorTypeName(factor.type);
      return false;
    }
    IsotropicEdge edge;
    edge.i = index.at(factor.keys[0]);
    edge.j = index.at(factor.keys[1]);
    const Eigen::VectorXd& z = factor.measurement;
    if (d == 2) {
      edge.R = RotationMatrix2D(z(2));
      edge.t = z.head(2);
    } else {
      edge.t = z.head(3);
      edge.R = Eigen::Quaterniond(z(6), z(3), z(4), z(5))
                   .normalized()
                   .toRotationMatrix();
    }
    if (!IsotropicWeightsFromInformation(factor.information, d, &edge.w)) {
      *error = "factor " + std::to_string(id) +
               ": information matrix blocks not positive definite";
      return false;
    }
    parent[Root(&parent, edge.i)] = Root(&parent, edge.j);
    problem->edges.push_back(std::move(edge));
  }
  for (int i = 1; i < n; ++i) {
    if (Root(&parent, i) != Root(&parent, 0)) {
      *error = "the certificate needs a connected pose graph";
      return false;
    }
  }
  return true;
}

SpMat IsotropicDataMatrix(const IsotropicProblem& p) {
  const int d = p.d;
  const int n = static_cast<int>(p.nodes.size());
  Triplets trip;
  trip.reserve(p.edges.size() * (2 * d + 2 * d * d + (d + 2) * (d + 2)));
  for (const IsotropicEdge& e : p.edges) {
    const double k = e.w.kappa, tau = e.w.tau;
    const int ri = n + d * e.i, rj = n + d * e.j;
    for (int a = 0; a < d; ++a) {
      trip.emplace_back(ri + a, ri + a, k);
      trip.emplace_back(rj + a, rj + a, k);
      for (int b = 0; b < d; ++b) {
        trip.emplace_back(ri + a, rj + b, -k * e.R(a, b));
        trip.emplace_back(rj + b, ri + a, -k * e.R(a, b));
      }
    }
    // b = e_tj - e_ti - sum_a tm_a e_(R_i col a); tau b b^T.
    std::vector<std::pair<int, double>> b = {{e.j, 1.0}, {e.i, -1.0}};
    for (int a = 0; a < d; ++a) b.emplace_back(ri + a, -e.t(a));
    for (const auto& [r, u] : b) {
      for (const auto& [c, v] : b) trip.emplace_back(r, c, tau * u * v);
    }
  }
  SpMat m(n + d * n, n + d * n);
  m.setFromTriplets(trip.begin(), trip.end());
  return m;
}

void GraphRotations(const Graph& graph, const IsotropicProblem& p,
                    Eigen::MatrixXd* rotations, Eigen::MatrixXd* translations) {
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  rotations->resize(d, d * n);
  translations->resize(d, n);
  for (int i = 0; i < n; ++i) {
    const std::vector<double>& v = graph.FindNode(p.nodes[i])->value;
    if (d == 2) {
      rotations->middleCols(2 * i, 2) = RotationMatrix2D(v[2]);
      translations->col(i) << v[0], v[1];
    } else {
      rotations->middleCols(3 * i, 3) =
          Eigen::Quaterniond(v[6], v[3], v[4], v[5])
              .normalized()
              .toRotationMatrix();
      translations->col(i) << v[0], v[1], v[2];
    }
  }
}

Eigen::MatrixXd DenseCertificateMatrix(const SpMat& m, int n, int d,
                                       const Eigen::MatrixXd& y) {
  ReducedBlocks b;
  std::string error;
  SplitDataMatrix(m, n, d, CertificateOptions(), &b, &error);
  const Eigen::MatrixXd tt(b.tt), tr(b.tr), rr(b.rr);
  const Eigen::MatrixXd q = rr - tr.transpose() * tt.ldlt().solve(tr);
  Eigen::MatrixXd s = q;
  const std::vector<Eigen::MatrixXd> lambda = LambdaBlocks(b, y);
  for (int i = 0; i < n; ++i) s.block(d * i, d * i, d, d) -= lambda[i];
  return s;
}

int RefineIsotropic(const IsotropicProblem& p, int max_iterations,
                    Eigen::MatrixXd* y) {
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const int r = static_cast<int>(y->rows());
  std::vector<double> rot(static_cast<size_t>(n) * r * r), tra(n * r);
  for (int i = 0; i < n; ++i) {
    Eigen::Map<Eigen::MatrixXd>(rot.data() + i * r * r, r, r) =
        CompleteToRotation(y->middleCols(n + d * i, d));
    Eigen::Map<Eigen::VectorXd>(tra.data() + i * r, r) = y->col(i);
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  RotationMatrixManifold manifold(r);
  for (const IsotropicEdge& e : p.edges) {
    problem.AddResidualBlock(new IsotropicEdgeCost(r, e), nullptr,
                             rot.data() + e.i * r * r, rot.data() + e.j * r * r,
                             tra.data() + e.i * r, tra.data() + e.j * r);
  }
  for (int i = 0; i < n; ++i) {
    problem.SetManifold(rot.data() + i * r * r, &manifold);
  }
  problem.SetParameterBlockConstant(rot.data());
  problem.SetParameterBlockConstant(tra.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  // Near a critical point from the g2o solution: Gauss-Newton steps (a
  // large first radius) converge in a few iterations; the tolerances are
  // the relative decrease and step that leave the certificate's lambda_min
  // at rounding level (its suboptimality bound is ~1e-10 f).
  options.initial_trust_region_radius = 1e12;
  options.function_tolerance = 1e-13;
  options.gradient_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  for (int i = 0; i < n; ++i) {
    y->middleCols(n + d * i, d) =
        Eigen::Map<const Eigen::MatrixXd>(rot.data() + i * r * r, r, r)
            .leftCols(d);
    y->col(i) = Eigen::Map<const Eigen::VectorXd>(tra.data() + i * r, r);
  }
  return static_cast<int>(summary.iterations.size()) - 1;
}

namespace {

// The isotropic objective at rank-d values y ([t | R], d x (n + d n)).
template <int D>
double EdgeObjectiveFixed(const IsotropicProblem& p, const Eigen::MatrixXd& y) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  const int n = static_cast<int>(p.nodes.size());
  double f = 0.0;
  for (const IsotropicEdge& e : p.edges) {
    const Mat ri = y.block<D, D>(0, n + D * e.i);
    const Mat rm = e.R;
    const Vec tm = e.t;
    f += e.w.kappa * (y.block<D, D>(0, n + D * e.j) - ri * rm).squaredNorm() +
         e.w.tau * (y.col(e.j).head<D>() - y.col(e.i).head<D>() - ri * tm)
                       .squaredNorm();
  }
  return f;
}
double EdgeObjective(const IsotropicProblem& p, const Eigen::MatrixXd& y) {
  return p.d == 2 ? EdgeObjectiveFixed<2>(p, y) : EdgeObjectiveFixed<3>(p, y);
}

// The Newton model of f at rank-d values y, in the variables of
// NewtonRefine (per free node: translation, then rotation tangent), kept
// per edge: J_e = [J_i J_j] (the residual's derivatives with respect to
// its two nodes' variables, (d^2 + d) x block each; a held node's block is
// unused), the residuals, and per node the retraction's curvature term.
// H = sum_e J_e^T J_e + blockdiag(curvature), g = sum_e J_e^T r_e: the
// Hessian is formed only to be factorized; products with it go edge by edge.
struct NewtonModel {
  int d = 0, q = 0, block = 0, n = 0, rows_per_edge = 0;
  Eigen::MatrixXd ji, jj;                  // Stacked per edge.
  Eigen::VectorXd residuals;               // Stacked per edge.
  std::vector<Eigen::MatrixXd> curvature;  // q x q per node (node 0 unused).
  Eigen::VectorXd gradient;

  int Col(int node) const { return block * (node - 1); }
  int Size() const { return block * (n - 1); }

  // H v, edge by edge.
  Eigen::VectorXd Times(const IsotropicProblem& p,
                        const Eigen::VectorXd& v) const {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(v.size());
    Eigen::VectorXd u(rows_per_edge);
    for (size_t k = 0; k < p.edges.size(); ++k) {
      const IsotropicEdge& e = p.edges[k];
      const auto bi = ji.middleRows(rows_per_edge * k, rows_per_edge);
      const auto bj = jj.middleRows(rows_per_edge * k, rows_per_edge);
      u.setZero();
      if (e.i > 0) u.noalias() += bi * v.segment(Col(e.i), block);
      if (e.j > 0) u.noalias() += bj * v.segment(Col(e.j), block);
      if (e.i > 0) out.segment(Col(e.i), block).noalias() += bi.transpose() * u;
      if (e.j > 0) out.segment(Col(e.j), block).noalias() += bj.transpose() * u;
    }
    for (int i = 1; i < n; ++i) {
      out.segment(Col(i) + d, q).noalias() +=
          curvature[i] * v.segment(Col(i) + d, q);
    }
    return out;
  }
  // Flops of Times: per edge four (rows x block) products, per node one
  // q x q.
  double TimesFlops(const IsotropicProblem& p) const {
    return 8.0 * rows_per_edge * block * static_cast<double>(p.edges.size()) +
           2.0 * q * q * n;
  }
};

// Assembles the lower triangle of a NewtonModel's H with node i's block at
// position[i] (nodes 1..n-1 on 0..n-2), as the factorizations read it, into
// a pattern built once per refinement: no triplets to sort on every call
// (assembling both triangles by triplets took 16-35 ms per Hessian on
// sphere2500, 35-45 ms on parking-garage, loaded machine).
class LowerHessianAssembler {
 public:
  LowerHessianAssembler(const IsotropicProblem& p,
                        const std::vector<int>& position, int block)
      : block_(block), position_(position) {
    const int n = static_cast<int>(p.nodes.size());
    // Per node, the positions of its neighbours placed after it: the
    // off-diagonal blocks below its diagonal block, in row order.
    std::vector<std::vector<int>> below(n);
    for (const IsotropicEdge& e : p.edges) {
      if (e.i == 0 || e.j == 0 || e.i == e.j) continue;
      const bool i_first = position[e.i] < position[e.j];
      below[i_first ? e.i : e.j].push_back(position[i_first ? e.j : e.i]);
    }
    std::vector<int> node_at(n - 1);
    for (int i = 1; i < n; ++i) {
      auto& list = below[i];
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
      node_at[position[i]] = i;
    }
    slot_.assign(p.edges.size(), -1);
    for (size_t k = 0; k < p.edges.size(); ++k) {
      const IsotropicEdge& e = p.edges[k];
      if (e.i == 0 || e.j == 0 || e.i == e.j) continue;
      const bool i_first = position[e.i] < position[e.j];
      const auto& list = below[i_first ? e.i : e.j];
      slot_[k] =
          static_cast<int>(std::lower_bound(list.begin(), list.end(),
                                            position[i_first ? e.j : e.i]) -
                           list.begin());
    }
    const int size = block * (n - 1);
    std::vector<int> outer(size + 1, 0);
    std::vector<int> inner;
    for (int pos = 0; pos < n - 1; ++pos) {
      const auto& list = below[node_at[pos]];
      for (int c = 0; c < block; ++c) {
        for (int r = c; r < block; ++r) inner.push_back(block * pos + r);
        for (int q : list) {
          for (int r = 0; r < block; ++r) inner.push_back(block * q + r);
        }
        outer[block * pos + c + 1] = static_cast<int>(inner.size());
      }
    }
    pattern_.resize(size, size);
    pattern_.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), pattern_.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
    std::fill_n(pattern_.valuePtr(), inner.size(), 0.0);
  }

  // Lower triangle of H (reads model's blocks and curvature).
  SpMat Assemble(const IsotropicProblem& p, const NewtonModel& model) const {
    using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                Eigen::ColMajor, 6, 6>;
    SpMat h = pattern_;
    double* values = h.valuePtr();
    const int* outer = h.outerIndexPtr();
    const int b = block_, rpe = model.rows_per_edge;
    // m's lower triangle into node i's diagonal block.
    auto add_diagonal = [&](int i, const Block& m) {
      const int col = b * position_[i];
      for (int c = 0; c < b; ++c) {
        for (int r = c; r < b; ++r) values[outer[col + c] + r - c] += m(r, c);
      }
    };
    Block product(b, b);
    for (size_t k = 0; k < p.edges.size(); ++k) {
      const IsotropicEdge& e = p.edges[k];
      const auto bi = model.ji.middleRows(rpe * k, rpe);
      const auto bj = model.jj.middleRows(rpe * k, rpe);
      if (e.i > 0) add_diagonal(e.i, product.noalias() = bi.transpose() * bi);
      if (e.j > 0) add_diagonal(e.j, product.noalias() = bj.transpose() * bj);
      if (e.i == 0 || e.j == 0) continue;
      product.noalias() = bi.transpose() * bj;
      if (e.i == e.j) {
        add_diagonal(e.i, product + product.transpose());
        continue;
      }
      // The block's rows are the later node's unknowns.
      const bool i_first = position_[e.i] < position_[e.j];
      const int col = b * position_[i_first ? e.i : e.j];
      for (int c = 0; c < b; ++c) {
        double* column = values + outer[col + c] + (b - c) + b * slot_[k];
        for (int r = 0; r < b; ++r) {
          column[r] += i_first ? product(c, r) : product(r, c);
        }
      }
    }
    const int q = model.q, d = model.d;
    for (int i = 1; i < model.n; ++i) {
      const int col = b * position_[i];
      for (int c = 0; c < q; ++c) {
        for (int r = c; r < q; ++r) {
          values[outer[col + d + c] + r - c] += model.curvature[i](r, c);
        }
      }
    }
    return h;
  }

 private:
  int block_;
  std::vector<int> position_;
  std::vector<int> slot_;  // Per edge: its off-diagonal block's place.
  SpMat pattern_;
};

// The per-edge part of LinearizeIsotropic with fixed-size d x d blocks (the
// dynamic-size version allocated a dozen temporaries per edge: 10-18 ms of a
// 2D graph's 50-90 ms certificate).
template <int D>
void LinearizeEdges(const IsotropicProblem& p, const Eigen::MatrixXd& y,
                    NewtonModel* model) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  constexpr int kQ = D == 2 ? 1 : 3;
  const int n = model->n, rpe = model->rows_per_edge;
  std::array<Mat, kQ> gens;
  if constexpr (D == 2) {
    gens[0] << 0, -1, 1, 0;
  } else {
    for (int k = 0; k < 3; ++k) gens[k] = Skew<double>(Vec::Unit(k));
  }
  for (size_t k = 0; k < p.edges.size(); ++k) {
    const IsotropicEdge& e = p.edges[k];
    const double sk = std::sqrt(e.w.kappa), st = std::sqrt(e.w.tau);
    const Mat rm = e.R;
    const Vec tm = e.t;
    const Mat ri = y.block<D, D>(0, n + D * e.i);
    const Mat rj = y.block<D, D>(0, n + D * e.j);
    const int row = rpe * static_cast<int>(k);
    Eigen::Map<Mat>(model->residuals.data() + row) = sk * (rj - ri * rm);
    model->residuals.segment<D>(row + D * D) =
        st * (y.col(e.j).head<D>() - y.col(e.i).head<D>() - ri * tm);
    auto bi = model->ji.middleRows(row, rpe);
    auto bj = model->jj.middleRows(row, rpe);
    for (int g = 0; g < kQ; ++g) {
      const Mat rig = ri * gens[g];
      const Mat dri = -sk * rig * rm;
      bi.col(D + g).template head<D * D>() =
          Eigen::Map<const Eigen::Matrix<double, D * D, 1>>(dri.data());
      bi.col(D + g).template tail<D>() = -st * rig * tm;
      const Mat drj = sk * rj * gens[g];
      bj.col(D + g).template head<D * D>() =
          Eigen::Map<const Eigen::Matrix<double, D * D, 1>>(drj.data());
    }
    for (int a = 0; a < D; ++a) {
      bi(D * D + a, a) = -st;
      bj(D * D + a, a) = st;
    }
    const auto r = model->residuals.segment(row, rpe);
    if (e.i > 0) {
      model->gradient.segment(model->Col(e.i), model->block).noalias() +=
          bi.transpose() * r;
    }
    if (e.j > 0) {
      model->gradient.segment(model->Col(e.j), model->block).noalias() +=
          bj.transpose() * r;
    }
  }
}

NewtonModel LinearizeIsotropic(const IsotropicProblem& p, const SpMat& m,
                               const Eigen::MatrixXd& y) {
  NewtonModel model;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const int q = d == 2 ? 1 : 3;
  model.d = d;
  model.q = q;
  model.n = n;
  model.block = d + q;
  model.rows_per_edge = d * d + d;
  const int rpe = model.rows_per_edge;
  const size_t edges = p.edges.size();
  model.ji = Eigen::MatrixXd::Zero(rpe * edges, model.block);
  model.jj = Eigen::MatrixXd::Zero(rpe * edges, model.block);
  model.residuals.resize(rpe * edges);
  model.gradient = Eigen::VectorXd::Zero(model.Size());
  if (d == 2) {
    LinearizeEdges<2>(p, y, &model);
  } else {
    LinearizeEdges<3>(p, y, &model);
  }
  // Second-order term of the retraction: sum_i tr(W_i^2 Lambda_i) with
  // Lambda_i = sym(P_i R_i), P = M Y^T: -tr(Lambda) (2D), Lambda -
  // tr(Lambda) I (3D) in the generators' coordinates.
  const Eigen::MatrixXd pm = m * y.transpose();
  model.curvature.assign(n, Eigen::MatrixXd::Zero(q, q));
  for (int i = 1; i < n; ++i) {
    const Eigen::MatrixXd pr =
        pm.middleRows(n + d * i, d) * y.middleCols(n + d * i, d);
    const Eigen::MatrixXd lambda = 0.5 * (pr + pr.transpose());
    model.curvature[i] =
        d == 2 ? Eigen::MatrixXd::Constant(1, 1, -lambda.trace())
               : Eigen::MatrixXd(lambda - lambda.trace() *
                                              Eigen::MatrixXd::Identity(3, 3));
  }
  return model;
}

}  // namespace

void IsotropicNewtonSystem(const IsotropicProblem& p, const SpMat& m,
                           const Eigen::MatrixXd& y, SpMat* hessian,
                           Eigen::VectorXd* gradient,
                           const std::vector<int>* node_order) {
  const NewtonModel model = LinearizeIsotropic(p, m, y);
  std::vector<int> position(model.n, model.n - 1);
  for (int i = 1; i < model.n; ++i) {
    position[i] = node_order != nullptr ? (*node_order)[i] : i - 1;
  }
  const SpMat lower =
      LowerHessianAssembler(p, position, model.block).Assemble(p, model);
  *hessian = lower.selfadjointView<Eigen::Lower>();
  *gradient = model.gradient;
}

Eigen::VectorXd IsotropicNewtonProduct(const IsotropicProblem& p,
                                       const SpMat& m, const Eigen::MatrixXd& y,
                                       const Eigen::VectorXd& v) {
  return LinearizeIsotropic(p, m, y).Times(p, v);
}
Eigen::MatrixXd RetractIsotropic(const IsotropicProblem& p,
                                 const Eigen::MatrixXd& y,
                                 const Eigen::VectorXd& step) {
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const int block = d + (d == 2 ? 1 : 3);
  Eigen::MatrixXd moved = y;
  for (int i = 1; i < n; ++i) {
    const Eigen::VectorXd s = step.segment(block * (i - 1), block);
    moved.col(i) += s.head(d);
    Eigen::MatrixXd rot;
    if (d == 2) {
      rot = RotationMatrix2D(s(2));
    } else {
      rot =
          QuaternionExp<double>(Eigen::Vector3d(s.tail(3))).toRotationMatrix();
    }
    moved.middleCols(n + d * i, d) = y.middleCols(n + d * i, d) * rot;
  }
  return moved;
}

namespace {

// Solves H s = rhs by conjugate gradients with products edge by edge,
// preconditioned by a factorization of the Hessian at an earlier point
// (near a minimum H changes little from one Newton step to the next, so a
// few iterations replace a factorization: one per refinement instead of
// one per step, as SE-Sync preconditions its truncated CG with a fixed
// Cholesky factor). It gives up (false) after max_iterations (CgBudget:
// a count of work, not of seconds, so that the result does not depend on
// the machine's load). Written out rather than
// Eigen's ConjugateGradient because it must detect negative curvature (then
// false: the caller factorizes the Hessian anew) and needs no assembled matrix.
bool PreconditionedCg(
    const IsotropicProblem& p, const NewtonModel& model,
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition,
    const Eigen::VectorXd& rhs, double relative_residual,
    double objective_tolerance, int max_iterations, Eigen::VectorXd* x) {
  x->setZero(rhs.size());
  Eigen::VectorXd r = rhs;
  Eigen::VectorXd z = precondition(r);
  Eigen::VectorXd dir = z;
  double rz = r.dot(z);
  const double target = relative_residual * rhs.norm();
  for (int k = 0; k < max_iterations; ++k) {
    // rz = r^T P^-1 r ~ r^T H^-1 r is what the step leaves of the model's
    // decrease (the objective above the exact Newton step's): the Euclidean
    // residual can stall on stiff directions that no longer matter
    // (parking-garage: |r| / |g| at 5e-3 from the 5th of 12 iterations,
    // rz at 5e-10 f, then a new factorization).
    if (r.norm() <= target || (k > 0 && rz <= objective_tolerance)) {
      return true;
    }
    const Eigen::VectorXd hd = model.Times(p, dir);
    const double curvature = dir.dot(hd);
    if (!(curvature > 0.0) || !(rz > 0.0)) return false;
    const double alpha = rz / curvature;
    *x += alpha * dir;
    r -= alpha * hd;
    z = precondition(r);
    const double rz_next = r.dot(z);
    dir = z + (rz_next / rz) * dir;
    rz = rz_next;
  }
  return r.norm() <= target || rz <= objective_tolerance;
}

}  // namespace

int CgBudget(double factor_flops, double factor_entries, double product_flops) {
  constexpr int kMinIterations = 10, kMaxIterations = 50;
  const double per_iteration = 4.0 * factor_entries + product_flops;
  if (!(per_iteration > 0.0)) return kMaxIterations;
  const double iterations = std::ceil(factor_flops / per_iteration);
  return static_cast<int>(std::clamp(iterations,
                                     static_cast<double>(kMinIterations),
                                     static_cast<double>(kMaxIterations)));
}

namespace {

// NewtonRefine with the blocks of M split already (CertifyGraph splits
// once for the refinement and the certificate).
int NewtonRefineSplit(const IsotropicProblem& p, const SpMat& m,
                      const ReducedBlocks& blocks, int max_iterations,
                      Eigen::MatrixXd* y, bool stop_early,
                      double supernodal_flops_per_entry,
                      std::map<std::string, double>* phase_seconds) {
  // CHOLMOD's supernodal factorization on one OpenMP thread (see
  // core/openmp_scope.h): sphere2500's Newton Hessian 0.088 -> 0.024 s.
  const SerialOpenMpScope serial_openmp;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  PhaseClock clock(phase_seconds);
  const int block = d == 2 ? 3 : 6;
  const std::vector<int> perm = HessianPermutation(blocks, block);
  const LowerHessianAssembler assembler(p, blocks.position, block);
  // Variable projection: the translations are kept optimal for the
  // rotations (node 0's held), so that each step is the Newton step of the
  // reduced objective min_t f(t, R). Without it the steps along the soft
  // translation modes overshoot far from the isotropic optimum (sphere2500:
  // 8 iterations instead of 3).
  auto project = [&](Eigen::MatrixXd* v) {
    const Eigen::VectorXd t0 = v->col(0);
    v->leftCols(n) = OptimalTranslations(blocks, v->rightCols(d * n));
    v->leftCols(n).colwise() += t0;
  };
  project(y);
  double f = EdgeObjective(p, *y);
  clock.Lap("line_search");
  // Near a minimum the Hessian is positive definite: Cholesky, its ordering
  // found once (the Hessian's pattern does not change); else LDL^T. The
  // factor of the first Hessian preconditions CG on the later ones; a new
  // one is made only when CG meets negative curvature or does not converge.
  PositiveDefiniteFactor llt(supernodal_flops_per_entry);
  Eigen::SimplicialLDLT<SpMat> ldlt;
  enum { kNone, kLlt, kLdlt } factor = kNone;
  bool analyzed = false;
  // The factors are of the permuted Hessian P H P^T.
  auto solve = [&](const Eigen::VectorXd& rhs) -> Eigen::VectorXd {
    Eigen::VectorXd permuted(rhs.size());
    for (Eigen::Index k = 0; k < rhs.size(); ++k) permuted(perm[k]) = rhs(k);
    const Eigen::VectorXd sol = factor == kLlt
                                    ? llt.Solve(permuted)
                                    : Eigen::VectorXd(ldlt.solve(permuted));
    Eigen::VectorXd out(rhs.size());
    for (Eigen::Index k = 0; k < rhs.size(); ++k) out(k) = sol(perm[k]);
    return out;
  };
  // Converged when the model's decrease g^T H^-1 g is at rounding level.
  auto converged = [&](const Eigen::VectorXd& g, const Eigen::VectorXd& step) {
    const double predicted = -g.dot(step);
    return predicted >= 0.0 && predicted <= 1e-13 * f;
  };
  // Inexact Newton (forcing terms): CG stops at a relative residual eta =
  // 1e-2 times the previous step's relative predicted decrease, in [1e-8,
  // 1e-3]; the error then shrinks by about eta per step on top of Newton's
  // quadratic rate (sphere2500's predicted decreases 0.2, 3.5e-4, 5.7e-8,
  // 1.7e-16 with exact steps).
  double eta = 1e-3;
  int it = 0;
  for (; it < max_iterations; ++it) {
    const NewtonModel model = LinearizeIsotropic(p, m, *y);
    const Eigen::VectorXd& g = model.gradient;
    clock.Lap("linearize");
    Eigen::VectorXd step;
    // With stop_early the certificate follows, and it needs the objective
    // within 1e-6 f of a critical point's: conjugate gradients stop once
    // the step leaves less than 1e-9 f of its decrease (parking-garage:
    // 8 iterations instead of 12 and a new factorization; its bound 8e-10 f
    // -> 2.4e-8 f, 1/40 of what it must prove). Without stop_early
    // (refining to the end) the convergence test below needs the forcing
    // term's accuracy.
    const double objective_tolerance = stop_early ? 1e-9 * f : 0.0;
    const bool cg =
        factor == kLlt &&
        PreconditionedCg(
            p, model, solve, -g, eta, objective_tolerance,
            CgBudget(llt.Flops(), llt.Entries(), model.TimesFlops(p)), &step);
    clock.Lap("cg");
    if (!cg) {
      const SpMat h = assembler.Assemble(p, model);
      clock.Lap("assemble");
      if (!analyzed) llt.Analyze(h);
      analyzed = true;
      clock.Lap("analyze");
      factor = kLlt;
      if (!llt.Factorize(h)) {
        ldlt.compute(h);
        if (ldlt.info() != Eigen::Success) return -1;
        factor = kLdlt;
      }
      clock.Lap("factorize");
      step = solve(-g);
      clock.Lap("solve");
    }
    if (!step.allFinite()) return -1;
    if (converged(g, step)) return it;
    const double predicted = -g.dot(step) / f;
    eta = std::clamp(1e-2 * predicted, 1e-8, 1e-3);
    // A full step from a predicted decrease p below 5e-4 f is the last (with
    // stop_early): the next predicted decrease is about C p^2 f with C <= 1.1
    // on the benchmark graphs (sphere2500 3.5e-4 -> 5.7e-8, torus3D 3.5e-5 ->
    // 1.4e-9, parking-garage 5.2e-6 -> 2.8e-11; 2D graphs C < 1e-3), and
    // the certificate's bound after it about 4 C p^2 f (sphere2500 2.1e-7 f,
    // torus3D 5.6e-9 f), below the 1e-6 f it must prove. The linearization
    // and solve that would confirm it, or take one more step (a CG solve of
    // 10-20 iterations on 3D graphs), are skipped; when the point is not
    // certified, CertifyGraph refines it to the end. 5e-4 is a guess from
    // these graphs, not a proven bound: a larger C costs that second
    // refinement, never the verdict.
    const bool last = stop_early && predicted <= 5e-4;
    // Retraction R_i Exp(W_i), translations projected, with backtracking.
    bool accepted = false;
    for (double alpha = 1.0; alpha > 1e-3 && !accepted; alpha *= 0.5) {
      Eigen::MatrixXd trial = RetractIsotropic(p, *y, alpha * step);
      project(&trial);
      const double f_trial = EdgeObjective(p, trial);
      if (f_trial <= f) {
        const double decrease = f - f_trial;
        *y = trial;
        f = f_trial;
        accepted = true;
        if (decrease <= 1e-15 * f || (last && alpha == 1.0)) {
          clock.Lap("line_search");
          return it + 1;
        }
      }
    }
    clock.Lap("line_search");
    if (!accepted) return it;  // No decrease left: at rounding level.
  }
  return it;
}

bool CertifySplit(const IsotropicProblem& p, const ReducedBlocks& b,
                  const Eigen::MatrixXd& y, const CertificateOptions& o,
                  CertificateResult* result, std::string* error) {
  // K's factorizations on one OpenMP thread (sphere2500: 0.045 -> 0.010 s).
  const SerialOpenMpScope serial_openmp;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  PhaseClock clock(&result->phase_seconds);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Eigen::MatrixXd> lambda = LambdaBlocks(b, y);
  double f = 0.0;
  for (const Eigen::MatrixXd& l : lambda) f += l.trace();
  result->objective = f;
  result->rank = static_cast<int>(y.rows());
  // Tolerance: the relative gap, not below rounding of the matrix entries.
  double scale = 0.0;
  for (int i = 0; i < b.rr.rows(); ++i) {
    scale = std::max(scale, std::abs(b.rr.coeff(i, i)));
  }
  result->delta =
      std::max(o.relative_gap * std::max(f, 0.0) / (d * n), 1e-12 * scale);
  clock.Lap("lambda");
  ShiftedCertificateOp op(b, lambda, o.supernodal_flops_per_entry,
                          &result->phase_seconds);
  // Inertia of K(-delta): S + delta I >= 0 iff no negative pivot. Else the
  // shift goes down by tens until it is below lambda_min.
  double sigma = -result->delta;
  op.set_shift(sigma);
  result->certified = op.ok() && op.NegativePivots() == 0;
  const double limit = -1e6 * std::max(scale, 1.0);
  while (!(op.ok() && op.NegativePivots() == 0) && sigma > limit) {
    sigma *= 10.0;
    op.set_shift(sigma);
  }
  clock = PhaseClock(&result->phase_seconds);
  result->factorizations = op.factorizations();
  if (!op.ok() || op.NegativePivots() > 0) {
    *error = "the shifted certificate matrix cannot be factorized";
    return false;
  }
  // Shift-and-invert Lanczos at sigma < lambda_min: the eigenvalue nearest
  // to sigma is lambda_min. It is far apart from the rest of the
  // spectrum of (S - sigma I)^-1 (sigma is next to it): 8 Lanczos vectors
  // suffice (city10000's eigenvalue search 0.25-0.29 s against 0.33-0.43 s
  // with 20, which took 21 solves; loaded machine). When certified, sigma =
  // -delta sits just below the d-fold cluster at lambda_min ~ 0 (the rows
  // of Y): d + 2 vectors take 5 solves instead of 9 on the 2D benchmark
  // graphs, 6-9 in 3D; uncertified, fewer than 8 take many more (MIT from
  // its file guess: 163 solves with 4 against 61).
  const int size = d * n;
  const int ncv = std::min(size, result->certified ? d + 2 : 8);
  Spectra::SymEigsShiftSolver<ShiftedCertificateOp> eigs(op, 1, ncv, sigma);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  if (eigs.info() != Spectra::CompInfo::Successful) {
    *error = "the Lanczos iteration for lambda_min did not converge";
    return false;
  }
  clock.Lap("lanczos");
  result->lambda_min = eigs.eigenvalues()(0);
  result->eigenvector = eigs.eigenvectors(1).col(0);
  result->lower_bound = f + d * n * std::min(result->lambda_min, 0.0);
  result->suboptimality_bound = f - result->lower_bound;
  result->eigen_seconds += SecondsSince(start);
  return true;
}

}  // namespace

int NewtonRefine(const IsotropicProblem& p, const SpMat& m, int max_iterations,
                 Eigen::MatrixXd* y, bool stop_early,
                 std::map<std::string, double>* phase_seconds) {
  ReducedBlocks blocks;
  std::string error;
  if (!SplitDataMatrix(m, static_cast<int>(p.nodes.size()), p.d,
                       CertificateOptions(), &blocks, &error)) {
    return -1;
  }
  return NewtonRefineSplit(p, m, blocks, max_iterations, y, stop_early,
                           CertificateOptions().supernodal_flops_per_entry,
                           phase_seconds);
}

bool CertifyRotations(const IsotropicProblem& p, const SpMat& m,
                      const Eigen::MatrixXd& y, const CertificateOptions& o,
                      CertificateResult* result, std::string* error) {
  ReducedBlocks b;
  if (!SplitDataMatrix(m, static_cast<int>(p.nodes.size()), p.d, o, &b,
                       error)) {
    return false;
  }
  return CertifySplit(p, b, y, o, result, error);
}

bool CertifyGraph(const Graph& graph, const CertificateOptions& options,
                  CertificateResult* result, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  *result = CertificateResult();
  PhaseClock clock(&result->phase_seconds);
  IsotropicProblem p;
  if (!BuildIsotropicProblem(graph, &p, error)) return false;
  clock.Lap("build_problem");
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const SpMat m = IsotropicDataMatrix(p);
  clock.Lap("build_matrix");
  Eigen::MatrixXd rotations, translations;
  GraphRotations(graph, p, &rotations, &translations);
  Eigen::MatrixXd y(d, n + d * n);
  y << translations, rotations;
  result->start_objective = (y * m * y.transpose()).trace();
  const Eigen::MatrixXd given = y;
  clock.Lap("build_values");
  ReducedBlocks blocks;
  if (!SplitDataMatrix(m, n, d, options, &blocks, error)) return false;
  clock.Lap("split");
  auto refine_start = std::chrono::steady_clock::now();
  // Refined with the early stop first; when that point is not certified,
  // refined to the end and certified again (the early stop must not turn a
  // certified graph into an uncertified one).
  result->refine_iterations = NewtonRefineSplit(
      p, m, blocks, options.max_refine_iterations, &y, true,
      options.supernodal_flops_per_entry, &result->phase_seconds);
  const bool newton = result->refine_iterations >= 0;
  if (!newton) {
    y = given;
    result->refine_iterations =
        RefineIsotropic(p, options.max_refine_iterations, &y);
  }
  result->refine_seconds = SecondsSince(refine_start);
  bool ok = CertifySplit(p, blocks, y.rightCols(d * n), options, result, error);
  if (newton && !(ok && result->certified)) {
    refine_start = std::chrono::steady_clock::now();
    const int more = NewtonRefineSplit(
        p, m, blocks, options.max_refine_iterations, &y, false,
        options.supernodal_flops_per_entry, &result->phase_seconds);
    result->refine_seconds += SecondsSince(refine_start);
    if (more >= 0) {
      result->refine_iterations += more;
      const int factorizations = result->factorizations;
      ok = CertifySplit(p, blocks, y.rightCols(d * n), options, result, error);
      result->factorizations += factorizations;
    }
  }
  clock = PhaseClock(&result->phase_seconds);
  double sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::MatrixXd rel =
        given.middleCols(n + d * i, d).transpose() * y.middleCols(n + d * i, d);
    const double c = std::clamp((rel.trace() - (d - 2)) / 2.0, -1.0, 1.0);
    result->max_rotation_difference =
        std::max(result->max_rotation_difference, std::acos(c));
    // Translations relative to node 0, which refining held fixed.
    sum_sq +=
        ((given.col(i) - given.col(0)) - (y.col(i) - y.col(0))).squaredNorm();
  }
  result->rms_translation_difference = std::sqrt(sum_sq / n);
  clock.Lap("differences");
  result->seconds = SecondsSince(start);
  return ok;
}

bool SolveIsotropicGlobally(Graph* graph, const CertificateOptions& options,
                            CertificateResult* result, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  *result = CertificateResult();
  IsotropicProblem p;
  if (!BuildIsotropicProblem(*graph, &p, error)) return false;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const SpMat m = IsotropicDataMatrix(p);
  ReducedBlocks b;
  if (!SplitDataMatrix(m, n, d, options, &b, error)) return false;
  Eigen::MatrixXd rotations, translations;
  GraphRotations(*graph, p, &rotations, &translations);
  Eigen::MatrixXd y(d, n + d * n);
  y << translations, rotations;
  int refine_iterations = RefineIsotropic(p, options.max_refine_iterations, &y);
  if (!CertifySplit(p, b, y.rightCols(d * n), options, result, error)) {
    return false;
  }
  int factorizations = result->factorizations;
  auto report = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  for (int r = d + 1; !result->certified && r <= d + options.max_rank_increase;
       ++r) {
    report("staircase: rank " + std::to_string(r - 1) +
           " not certified (lambda_min " + std::to_string(result->lambda_min) +
           "), descending at rank " + std::to_string(r) + " (" +
           std::to_string(SecondsSince(start)) + " s)");
    // Lift to rank r (a zero row) and descend along the new row set to the
    // eigenvector of lambda_min: second-order decrease lambda_min alpha^2.
    Eigen::MatrixXd yr = Eigen::MatrixXd::Zero(r, d * n);
    yr.topRows(r - 1) = y.rightCols(d * n);
    const double f0 = ReducedObjective(b, yr);
    Eigen::MatrixXd dot = Eigen::MatrixXd::Zero(r, d * n);
    dot.row(r - 1) = result->eigenvector.transpose();
    Eigen::MatrixXd best;
    for (double alpha = std::sqrt(static_cast<double>(n)); alpha > 1e-12;
         alpha *= 0.5) {
      Eigen::MatrixXd trial = yr + alpha * dot;
      for (int i = 0; i < n; ++i) {
        trial.middleCols(d * i, d) =
            ProjectToStiefel(trial.middleCols(d * i, d));
      }
      if (ReducedObjective(b, trial) < f0) {
        best = trial;
        break;
      }
    }
    if (best.size() == 0) {
      *error = "no descent from the saddle at rank " + std::to_string(r - 1);
      return false;
    }
    y.resize(r, n + d * n);
    y << OptimalTranslations(b, best), best;
    const int iterations =
        RefineIsotropic(p, options.max_refine_iterations, &y);
    refine_iterations += iterations;
    report("staircase: rank " + std::to_string(r) + " refined in " +
           std::to_string(iterations) + " iterations (" +
           std::to_string(SecondsSince(start)) + " s)");
    if (!CertifySplit(p, b, y.rightCols(d * n), options, result, error)) {
      return false;
    }
    factorizations += result->factorizations;
  }
  result->refine_iterations = refine_iterations;
  result->factorizations = factorizations;
  result->seconds = SecondsSince(start);
  const bool certified = result->certified;
  if (!certified) {
    *error = "the staircase ended uncertified at rank " +
             std::to_string(result->rank);
  }
  // Rounding: the best rank-d approximation Sigma_d V_d^T = U_d^T Y of Y
  // (top eigenvectors of Y Y^T), the sign giving most blocks det > 0, each
  // block projected onto SO(d).
  const Eigen::MatrixXd yr = y.rightCols(d * n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(yr * yr.transpose());
  const int r = static_cast<int>(yr.rows());
  Eigen::MatrixXd rounded =
      eig.eigenvectors().rightCols(d).transpose() * yr;  // d x dn.
  int positive = 0;
  for (int i = 0; i < n; ++i) {
    positive += rounded.middleCols(d * i, d).determinant() > 0;
  }
  if (2 * positive < n) rounded.row(d - 1) *= -1.0;
  for (int i = 0; i < n; ++i) {
    rounded.middleCols(d * i, d) =
        ProjectToRotation(rounded.middleCols(d * i, d));
  }
  (void)r;
  Eigen::MatrixXd t = OptimalTranslations(b, rounded);
  // Gauge: the fixed node (else node 0) keeps its pose: X_i <- G X_i.
  int anchor = 0;
  for (int i = 0; i < n; ++i) {
    if (graph->FindNode(p.nodes[i])->fixed) anchor = i;
  }
  const Eigen::MatrixXd g_rot = rotations.middleCols(d * anchor, d) *
                                rounded.middleCols(d * anchor, d).transpose();
  const Eigen::VectorXd g_tra =
      translations.col(anchor) - g_rot * t.col(anchor);
  for (int i = 0; i < n; ++i) {
    const Eigen::MatrixXd rot = g_rot * rounded.middleCols(d * i, d);
    const Eigen::VectorXd tra = g_rot * t.col(i) + g_tra;
    std::vector<double>& v = graph->FindNode(p.nodes[i])->value;
    if (d == 2) {
      v[0] = tra(0);
      v[1] = tra(1);
      v[2] = std::atan2(rot(1, 0), rot(0, 0));
    } else {
      const Eigen::Matrix3d rot3 = rot;
      const Eigen::Quaterniond q(rot3);
      for (int k = 0; k < 3; ++k) v[k] = tra(k);
      v[3] = q.x();
      v[4] = q.y();
      v[5] = q.z();
      v[6] = q.w();
    }
  }
  result->rounded_uncertified = !certified;
  return certified;
}

}  // namespace slam
