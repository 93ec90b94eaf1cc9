// Certificate of global optimality for pose graphs and the Riemannian
// staircase that escapes local minima (SE-Sync: Rosen, Carlone, Bandeira,
// Leonard, "SE-Sync: a certifiably correct algorithm for synchronization
// over the special Euclidean group", IJRR 2019). Written from the paper.
//
// The certified problem is the ISOTROPIC approximation of the pose graph:
//   f(t, R) = sum_e kappa_e |R_j - R_i Rm_e|_F^2 + tau_e |t_j - t_i - R_i
//   tm_e|^2
// over R_i in SO(d), t_i in R^d, with one scalar kappa (rotation) and tau
// (translation) per relative-pose factor taken from its information matrix
// as SE-Sync's g2o loader does (IsotropicWeightsFromInformation). This is
// not the g2o objective (sum e^T Omega e with the full matrices and the
// geodesic angle), so a certificate proves the optimum of f, not of chi2.
//
// Translations are eliminated in closed form: with Y = [t_1..t_n R_1..R_n]
// (r x (n + dn), r >= d) f = tr(Y M Y^T) for a sparse symmetric data matrix
// M, and min over t gives tr(Y_R Q Y_R^T) with Q = M_RR - M_Rt M_tt^+ M_tR
// (dense, never formed: every operation below uses the sparse matrix
// K = [M_tt M_tR; M_Rt M_RR - Lambda - sigma I] with node 0's translation
// grounded, whose Schur complement is S - sigma I).
//
// At a first-order critical point Y_R, Lambda = SymBlockDiag_d(Q Y_R^T Y_R)
// and S = Q - Lambda. If S >= 0, Y_R is a global minimizer of the
// semidefinite relaxation; with rank d it is the global optimum of f. For
// any lambda_min(S) the relaxation's value is at least
//   f(Y_R) + d n min(lambda_min, 0)
// (tr(QZ) = tr(SZ) + tr(Lambda) >= d n lambda_min + f for every feasible Z),
// which is the lower bound reported. Certified iff lambda_min >= -delta.
#ifndef SLAM_CORE_CERTIFICATE_H_
#define SLAM_CORE_CERTIFICATE_H_

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/graph.h"

namespace slam {

struct IsotropicWeights {
  double kappa = 0.0;  // Rotation concentration.
  double tau = 0.0;    // Translation precision.
};

// SE-Sync's rule (its g2o loader): with Omega_t the translation block and
// Omega_R the rotation block of the g2o information matrix,
//   2D (x, y, theta): tau = 2 / tr(Omega_t^-1), kappa = Omega_theta,theta;
//   3D (t, qvec):     tau = 3 / tr(Omega_t^-1), kappa = 3 / (2 tr(Omega_R^-1)).
// Returns false when a block is not positive definite.
bool IsotropicWeightsFromInformation(const Eigen::MatrixXd& information,
                                     int dim, IsotropicWeights* weights);

struct IsotropicEdge {
  int i = 0, j = 0;   // Node indices.
  Eigen::MatrixXd R;  // Measured rotation of X_i^-1 X_j (d x d).
  Eigen::VectorXd t;  // Measured translation (d).
  IsotropicWeights w;
};

struct IsotropicProblem {
  int d = 0;               // 2 or 3.
  std::vector<Key> nodes;  // Index -> key.
  std::vector<IsotropicEdge> edges;
};

// The isotropic problem of a pose graph: only SE(2) or only SE(3) relative
// pose factors, no priors or other factors, connected, at most one fixed
// node (the gauge). Returns false with *error otherwise.
bool BuildIsotropicProblem(const Graph& graph, IsotropicProblem* problem,
                           std::string* error);

// The data matrix M over [t_1..t_n, vec blocks R_1..R_n] (n + d n square).
Eigen::SparseMatrix<double> IsotropicDataMatrix(const IsotropicProblem& p);

// Rotations of the graph's nodes as Y_R (d x d n), translations (d x n).
void GraphRotations(const Graph& graph, const IsotropicProblem& p,
                    Eigen::MatrixXd* rotations, Eigen::MatrixXd* translations);

struct CertificateOptions {
  // delta = relative_gap * f / (d n): certified when the bound it proves,
  // d n max(-lambda_min, 0), is at most relative_gap * f.
  double relative_gap = 1e-6;
  // Before certifying, the rotations are refined to a critical point of f
  // (LM on f from the given values; they come from the g2o objective).
  int max_refine_iterations = 100;
  // Staircase: ranks d+1 .. d + max_rank_increase.
  int max_rank_increase = 3;
  // CHOLMOD's supernodal Cholesky for a matrix whose symbolic analysis
  // counts at least this many flops per factor entry (dense fronts:
  // sphere2500's Newton Hessian 234, torus3D 325, city10000 81), Eigen's
  // simplicial one below (parking-garage 52, manhattan 35, intel 17). With
  // OpenBLAS and CHOLMOD on one OpenMP thread, city10000's Newton
  // Hessian factorizes in 0.024-0.034 s supernodal against 0.042-0.046 s
  // simplicial, parking-garage's in 0.013-0.027 s against 0.009 s: 64 is a
  // guess between those two graphs (CHOLMOD's own switch is 40). It moves
  // the time only, never the verdict. Tests set 0 or a huge value to take
  // either path.
  double supernodal_flops_per_entry = 64.0;
  // The elimination order of the pose graph that every factorization of
  // the certificate shares: kAuto takes AMD's, or METIS's nested
  // dissection where it counts fewer flops (tried only on 3D graphs whose
  // factors have dense fronts by the threshold above: sphere2500,
  // torus3D); tests force either.
  enum class Ordering { kAuto, kAmd, kNestedDissection };
  Ordering ordering = Ordering::kAuto;
  // Called with one line per stage of the staircase (a rank refined can
  // take minutes on a large 3D graph: torus3D from its file guess); may be
  // empty.
  std::function<void(const std::string&)> progress;
};

struct CertificateResult {
  bool certified = false;
  double lambda_min = 0.0;
  double delta = 0.0;
  double objective = 0.0;            // f at the refined critical point.
  double lower_bound = 0.0;          // f + d n min(lambda_min, 0).
  double suboptimality_bound = 0.0;  // objective - lower_bound.
  double start_objective = 0.0;      // f at the values given (before refining).
  int rank = 0;                      // Rank of the relaxation certified.
  int refine_iterations = 0;
  int factorizations = 0;  // Of K, for the eigenvalue search.
  double seconds = 0.0;
  double refine_seconds = 0.0;  // Of which refining to a critical point.
  double eigen_seconds = 0.0;   // ... and finding lambda_min.
  // Where the time went, by phase (build, split, linearize, assemble,
  // factorize, cg, line_search, lambda, k_assemble, k_factorize, lanczos,
  // ...), summed over the calls.
  std::map<std::string, double> phase_seconds;
  // The given values against the refined critical point of f (rank d only):
  // largest rotation difference (radians) and RMS translation difference.
  double max_rotation_difference = 0.0;
  double rms_translation_difference = 0.0;
  Eigen::VectorXd eigenvector;  // Of lambda_min (d n), when not certified.
  // SolveIsotropicGlobally only: the staircase's last iterate was rounded
  // and written into the graph although it is not certified (see there).
  bool rounded_uncertified = false;
};

// Smallest eigenvalue (and eigenvector) of S = Q - Lambda(Y_R) for a
// critical point Y_R (r x d n) of the reduced problem, by shift-and-invert
// Lanczos (Spectra) on sparse factorizations of K; also the objective.
bool CertifyRotations(const IsotropicProblem& p,
                      const Eigen::SparseMatrix<double>& M,
                      const Eigen::MatrixXd& Y, const CertificateOptions& o,
                      CertificateResult* result, std::string* error);

// The dense certificate matrix S (tests, small graphs only).
Eigen::MatrixXd DenseCertificateMatrix(const Eigen::SparseMatrix<double>& M,
                                       int n, int d, const Eigen::MatrixXd& Y);

// Locally minimizes f over rank-r variables (Y_R r x d n with orthonormal
// d-column blocks, translations r x n) from *Y by LM on a Stiefel
// parametrization; returns the iterations.
int RefineIsotropic(const IsotropicProblem& p, int max_iterations,
                    Eigen::MatrixXd* Y);

// Rank d only, in the variables of NewtonRefine (per node 1..n-1: its
// translation, then its rotation's tangent W_i in the generators' basis,
// retraction R_i Exp(W_i); node 0 held): f(Retract(y, w)) = f(y) + 2 g^T w
// + w^T H w + O(|w|^3). H is the exact Hessian of that pullback.
// node_order (optional): node i's block at position node_order[i] (nodes
// 1..n-1 on 0..n-2, as NewtonRefine assembles it in its elimination
// order); natural order without it. H is returned with both triangles.
void IsotropicNewtonSystem(const IsotropicProblem& p,
                           const Eigen::SparseMatrix<double>& m,
                           const Eigen::MatrixXd& y,
                           Eigen::SparseMatrix<double>* hessian,
                           Eigen::VectorXd* gradient,
                           const std::vector<int>* node_order = nullptr);
// H v without forming H (edge by edge), as NewtonRefine's conjugate
// gradients use it.
Eigen::VectorXd IsotropicNewtonProduct(const IsotropicProblem& p,
                                       const Eigen::SparseMatrix<double>& m,
                                       const Eigen::MatrixXd& y,
                                       const Eigen::VectorXd& v);
Eigen::MatrixXd RetractIsotropic(const IsotropicProblem& p,
                                 const Eigen::MatrixXd& y,
                                 const Eigen::VectorXd& step);

// NewtonRefine's conjugate gradients give up (and the Hessian is factorized
// anew) after this many iterations: as many as cost the flops of one
// factorization (factor_flops, CHOLMOD's count for its pattern), an
// iteration costing a solve with the factor (4 factor_entries) and one
// Hessian product (product_flops), clamped to [10, 50]. A count of work,
// never of seconds: until this session the limit was half the last
// factorization's wall time, and the same graph took a second
// factorization or not with the machine's load (sphere2500: its second
// step's 17 iterations cut at 11 on a loaded machine, then 0.19 s more
// for a factorization; its lambda_min -5.12e-8 or -4.80e-8 from run to
// run). The floor: a simplicial factorization runs at a third or less of
// the flop rate of the solves (parking-garage 2.2e7 flops in about 50 ms,
// its CG 5.3e6 flops an iteration in 3.7 ms), a supernodal one at about
// twice theirs (sphere2500 4e8 flops in 0.25 s, 9e6 an iteration in 4-11
// ms), so a flop count alone would cut parking-garage's 8 iterations at 4.
int CgBudget(double factor_flops, double factor_entries, double product_flops);

// Rank d only: Riemannian Newton steps on f (rotations, node 0 held; the
// exact Hessian of IsotropicNewtonSystem, tested against finite
// differences), the translations kept optimal for the rotations (variable
// projection: Newton on min_t f(t, R)), with backtracking. The Hessian is
// factorized once; later steps solve by conjugate gradients preconditioned
// with that factor (a new factorization only when they fail). Returns the
// iterations, or -1 when the Newton system cannot be solved (far from a
// minimum). stop_early: a full step whose predicted decrease is below
// 5e-4 f is the last (quadratic convergence puts the next one far below
// the certificate's tolerance) instead of confirming that with one more
// linearization and solve, and conjugate gradients stop once the objective
// they leave above the exact Newton step's is below 1e-9 f.
int NewtonRefine(const IsotropicProblem& p,
                 const Eigen::SparseMatrix<double>& m, int max_iterations,
                 Eigen::MatrixXd* y, bool stop_early = false,
                 std::map<std::string, double>* phase_seconds = nullptr);

// Certifies the graph's current values: refines them to a critical point
// of f (rank d) and certifies that.
bool CertifyGraph(const Graph& graph, const CertificateOptions& options,
                  CertificateResult* result, std::string* error);

// The Riemannian staircase from the graph's values: ranks d+1, d+2, ...
// (escaping along the eigenvector of lambda_min) until the relaxation is
// certified, then rounding to SO(d)^n and the translations by least
// squares, written into the graph (the fixed node, if any, keeps its pose).
// *result describes the relaxation's certificate (its lower bound is a
// lower bound for f). Returns false when the staircase ends uncertified;
// its last iterate (the highest rank refined) is then rounded and written
// all the same (result->rounded_uncertified): not a certified optimum, but
// a start from which LM may reach a lower minimum than from the caller's
// values, which the caller keeps otherwise. On other failures the graph is
// unchanged.
bool SolveIsotropicGlobally(Graph* graph, const CertificateOptions& options,
                            CertificateResult* result, std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_CERTIFICATE_H_
