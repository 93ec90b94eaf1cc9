// Tests of the pose-graph certificate (core/certificate.h): SE-Sync's
// isotropic weights against hand-computed values; the data matrix against
// the objective summed edge by edge; lambda_min by shift-and-invert Lanczos
// against a dense eigensolver; a graph with a known global optimum
// certified; a graph driven into a local minimum (a twisted cycle) not
// certified, then escaped by the staircase to the global optimum.
#include <atomic>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "core/certificate.h"
#include "core/graph.h"
#include "core/initialization.h"
#include "core/lie.h"
#include "core/optimizer.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Rng = ::slam::testing::TestRng;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

TEST(IsotropicWeightsTest, SE2AndSE3AsSESyncsLoader) {
  Eigen::MatrixXd info2(3, 3);
  info2 << 4, 1, 0, 1, 2, 0, 0, 0, 9;
  IsotropicWeights w;
  ASSERT_TRUE(IsotropicWeightsFromInformation(info2, 2, &w));
  // [4 1; 1 2]^-1 has trace 6/7: tau = 2 / (6/7); kappa = I33.
  EXPECT_NEAR(w.tau, 7.0 / 3.0, 1e-12);
  EXPECT_NEAR(w.kappa, 9.0, 1e-12);
  Eigen::MatrixXd info3 = Eigen::MatrixXd::Zero(6, 6);
  info3.diagonal() << 1, 2, 4, 2, 4, 8;
  ASSERT_TRUE(IsotropicWeightsFromInformation(info3, 3, &w));
  EXPECT_NEAR(w.tau, 3.0 / 1.75, 1e-12);           // 3 / tr(diag(1,2,4)^-1)
  EXPECT_NEAR(w.kappa, 3.0 / (2 * 0.875), 1e-12);  // 3 / (2 tr(...))
  info3(0, 0) = -1.0;
  EXPECT_FALSE(IsotropicWeightsFromInformation(info3, 3, &w));
}

// A 2D cycle of n poses on a circle (heading along it) with odometry and
// chords between poses k and k + n/2; measurements with noise.
void BuildCycle2(int n, double noise_t, double noise_r, unsigned seed,
                 Graph* graph, bool chords = true) {
  Rng rng(seed);
  std::vector<Pose2> gt;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    gt.emplace_back(5 * std::cos(a), 5 * std::sin(a), a + M_PI / 2);
    graph->AddNode(Pose2Key(k), Pose2Value(gt.back()));
  }
  Eigen::Matrix3d info = Eigen::Matrix3d::Identity();
  info.topLeftCorner<2, 2>() *= 100.0;
  info(0, 1) = info(1, 0) = 20.0;
  info(2, 2) = 400.0;
  auto add = [&](int i, int j) {
    const Pose2 noise(noise_t * rng.Normal(), noise_t * rng.Normal(),
                      noise_r * rng.Normal());
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(i), Pose2Key(j),
                               gt[i].Inverse() * gt[j] * noise, info, &f,
                               &error));
    graph->AddFactor(std::move(f));
  };
  for (int k = 0; k < n; ++k) add(k, (k + 1) % n);
  if (!chords) return;
  for (int k = 0; k < n / 2; k += 3) add(k, k + n / 2);
}

// A 3D helix of two turns with loop closures between the turns.
void BuildHelix3(int per_turn, double noise, unsigned seed, Graph* graph) {
  Rng rng(seed);
  std::vector<Pose3> gt;
  for (int k = 0; k < 2 * per_turn; ++k) {
    const double a = 2 * M_PI * k / per_turn;
    gt.emplace_back(
        Eigen::Vector3d(10 * std::cos(a), 10 * std::sin(a), 0.5 * k),
        Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())));
    graph->AddNode(Pose3Key(k), Pose3Value(gt.back()));
  }
  Matrix6d info = Matrix6d::Identity() * 100.0;
  info(0, 1) = info(1, 0) = 10.0;
  info.bottomRightCorner<3, 3>() *= 4.0;
  auto add = [&](int i, int j) {
    const Pose3 error_pose(noise * rng.Normal3(),
                           QuaternionExp<double>(noise * rng.Normal3()));
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(j),
                               gt[i].Inverse() * gt[j] * error_pose, info, &f,
                               &error));
    graph->AddFactor(std::move(f));
  };
  for (int k = 0; k + 1 < 2 * per_turn; ++k) add(k, k + 1);
  for (int k = 0; k < per_turn; k += 2) add(k, k + per_turn);
}

double EdgeSum(const IsotropicProblem& p, const Eigen::MatrixXd& y) {
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  double f = 0.0;
  for (const IsotropicEdge& e : p.edges) {
    const Eigen::MatrixXd ri = y.middleCols(n + d * e.i, d);
    const Eigen::MatrixXd rj = y.middleCols(n + d * e.j, d);
    f += e.w.kappa * (rj - ri * e.R).squaredNorm() +
         e.w.tau * (y.col(e.j) - y.col(e.i) - ri * e.t).squaredNorm();
  }
  return f;
}

TEST(CertificateTest, DataMatrixGivesTheObjective) {
  Graph graph;
  BuildHelix3(8, 0.05, 3, &graph);
  IsotropicProblem p;
  std::string error;
  ASSERT_TRUE(BuildIsotropicProblem(graph, &p, &error)) << error;
  const Eigen::SparseMatrix<double> m = IsotropicDataMatrix(p);
  Rng rng(5);
  const int n = static_cast<int>(p.nodes.size());
  for (int r : {3, 5}) {
    Eigen::MatrixXd y(r, n + 3 * n);
    for (int i = 0; i < y.rows(); ++i) {
      for (int j = 0; j < y.cols(); ++j) y(i, j) = rng.Normal();
    }
    EXPECT_NEAR((y * m * y.transpose()).trace(), EdgeSum(p, y),
                1e-9 * EdgeSum(p, y));
  }
}

// Refines the graph's values on f, certifies, and compares lambda_min with
// the dense eigensolver's.
CertificateResult CheckAgainstDense(
    const Graph& graph, int rank_extra = 0,
    const CertificateOptions& options = CertificateOptions()) {
  IsotropicProblem p;
  std::string error;
  EXPECT_TRUE(BuildIsotropicProblem(graph, &p, &error)) << error;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const Eigen::SparseMatrix<double> m = IsotropicDataMatrix(p);
  Eigen::MatrixXd rot, tra;
  GraphRotations(graph, p, &rot, &tra);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(d + rank_extra, n + d * n);
  y.topRows(d) << tra, rot;
  RefineIsotropic(p, 200, &y);
  CertificateResult result;
  EXPECT_TRUE(
      CertifyRotations(p, m, y.rightCols(d * n), options, &result, &error))
      << error;
  const Eigen::MatrixXd s = DenseCertificateMatrix(m, n, d, y.rightCols(d * n));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  const double dense = eig.eigenvalues()(0);
  EXPECT_NEAR(result.lambda_min, dense,
              1e-7 * std::max(1.0, eig.eigenvalues().cwiseAbs().maxCoeff()));
  EXPECT_EQ(result.certified, dense >= -result.delta);
  // Stationarity: S Y^T = 0 at the refined critical point.
  EXPECT_LT((s * y.rightCols(d * n).transpose()).norm(), 1e-6 * s.norm());
  return result;
}

// NewtonRefine's system against finite differences of the pullback
// phi(w) = f(Retract(y, w)) at a point that is not critical (so that the
// curvature term of the retraction, sum_i tr(W_i^2 Lambda_i), matters):
// gradient 2 g against central differences of phi, Hessian 2 H against
// central differences of that numeric gradient, entry by entry. Dropping
// the curvature term (Gauss-Newton's J^T J) fails this by far.
void CheckNewtonSystem(const Graph& graph, double perturbation) {
  IsotropicProblem p;
  std::string error;
  ASSERT_TRUE(BuildIsotropicProblem(graph, &p, &error)) << error;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const Eigen::SparseMatrix<double> m = IsotropicDataMatrix(p);
  Eigen::MatrixXd rot, tra;
  GraphRotations(graph, p, &rot, &tra);
  Eigen::MatrixXd y(d, n + d * n);
  y << tra, rot;
  const int block = d == 2 ? 3 : 6;
  Rng rng(11);
  Eigen::VectorXd shake(block * (n - 1));
  for (int k = 0; k < shake.size(); ++k) shake(k) = perturbation * rng.Normal();
  y = RetractIsotropic(p, y, shake);
  Eigen::SparseMatrix<double> h;
  Eigen::VectorXd g;
  IsotropicNewtonSystem(p, m, y, &h, &g);
  const Eigen::MatrixXd hd(h);
  ASSERT_EQ(hd.rows(), block * (n - 1));
  // The products NewtonRefine's conjugate gradients use, edge by edge,
  // against the assembled Hessian.
  Eigen::VectorXd v(hd.rows());
  for (int k = 0; k < v.size(); ++k) v(k) = rng.Normal();
  EXPECT_LT((IsotropicNewtonProduct(p, m, y, v) - hd * v).norm(),
            1e-12 * (hd * v).norm());
  // Assembled in another node order (as NewtonRefine does, in its
  // elimination order): the same matrix with its blocks renumbered.
  std::vector<int> order(n);
  order[0] = n - 1;
  for (int i = 1; i < n; ++i) order[i] = n - 1 - i;  // Reversed.
  Eigen::SparseMatrix<double> h_ordered;
  Eigen::VectorXd g_unused;
  IsotropicNewtonSystem(p, m, y, &h_ordered, &g_unused, &order);
  const Eigen::MatrixXd hod(h_ordered);
  double max_difference = 0.0;
  for (int i = 1; i < n; ++i) {
    for (int j = 1; j < n; ++j) {
      max_difference = std::max(
          max_difference,
          (hod.block(block * order[i], block * order[j], block, block) -
           hd.block(block * (i - 1), block * (j - 1), block, block))
              .cwiseAbs()
              .maxCoeff());
    }
  }
  EXPECT_LT(max_difference, 1e-12 * hd.cwiseAbs().maxCoeff());
  auto phi = [&](const Eigen::VectorXd& w) {
    return EdgeSum(p, RetractIsotropic(p, y, w));
  };
  // phi is smooth; central differences have O(eps^2) truncation error.
  const double eps = 1e-4;
  auto numeric_gradient = [&](const Eigen::VectorXd& w) {
    Eigen::VectorXd grad(w.size());
    for (int a = 0; a < w.size(); ++a) {
      Eigen::VectorXd plus = w, minus = w;
      plus(a) += eps;
      minus(a) -= eps;
      grad(a) = (phi(plus) - phi(minus)) / (2 * eps);
    }
    return grad;
  };
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(hd.rows());
  const Eigen::VectorXd grad = numeric_gradient(zero);
  EXPECT_LT((2 * g - grad).norm(), 1e-6 * grad.norm());
  Eigen::MatrixXd numeric(hd.rows(), hd.cols());
  for (int b = 0; b < hd.cols(); ++b) {
    Eigen::VectorXd plus = zero, minus = zero;
    plus(b) = eps;
    minus(b) = -eps;
    numeric.col(b) =
        (numeric_gradient(plus) - numeric_gradient(minus)) / (2 * eps);
  }
  const Eigen::MatrixXd numeric_sym = 0.5 * (numeric + numeric.transpose());
  const double tol = 1e-5 * numeric_sym.norm();
  EXPECT_LT((2 * hd - numeric_sym).norm(), tol);
  // The curvature term (Frobenius norm of its blocks Lambda_i - tr(Lambda_i)
  // I, or -tr(Lambda_i) in 2D) is far above the tolerance: without it the
  // comparison above fails.
  const Eigen::MatrixXd pm = m * y.transpose();
  double curvature_sq = 0.0;
  for (int i = 1; i < n; ++i) {
    const Eigen::MatrixXd pr =
        pm.middleRows(n + d * i, d) * y.middleCols(n + d * i, d);
    const Eigen::MatrixXd lambda = 0.5 * (pr + pr.transpose());
    curvature_sq +=
        d == 2 ? lambda.trace() * lambda.trace()
               : (lambda - lambda.trace() * Eigen::MatrixXd::Identity(3, 3))
                     .squaredNorm();
  }
  EXPECT_GT(2 * std::sqrt(curvature_sq), 100 * tol);
}

TEST(CertificateTest, NewtonHessianMatchesFiniteDifferences) {
  Graph cycle;
  BuildCycle2(8, 0.05, 0.05, 3, &cycle);
  CheckNewtonSystem(cycle, 0.3);
  Graph helix;
  BuildHelix3(4, 0.05, 4, &helix);
  CheckNewtonSystem(helix, 0.3);
}

// With the translations optimal for the rotations, the Newton Hessian's
// Schur complement on the rotation tangents is sum_k C_k^T S C_k: C_k maps
// the tangents w to the k-th rows of the perturbation R_i G(w_i) (node 0
// held), S = Q - Lambda the certificate matrix. This ties the refinement's
// Hessian to the certificate matrix (a factor of K gives S^-1, which can
// precondition the reduced Newton system), at a point that is not critical.
void CheckReducedHessian(const Graph& graph) {
  IsotropicProblem p;
  std::string error;
  ASSERT_TRUE(BuildIsotropicProblem(graph, &p, &error)) << error;
  const int d = p.d, n = static_cast<int>(p.nodes.size());
  const int q = d == 2 ? 1 : 3, block = d + q;
  const Eigen::SparseMatrix<double> m = IsotropicDataMatrix(p);
  Eigen::MatrixXd rot, tra;
  GraphRotations(graph, p, &rot, &tra);
  Eigen::MatrixXd y(d, n + d * n);
  y << tra, rot;
  Rng rng(3);
  Eigen::VectorXd shake(block * (n - 1));
  for (int k = 0; k < shake.size(); ++k) shake(k) = 0.2 * rng.Normal();
  y = RetractIsotropic(p, y, shake);
  NewtonRefine(p, m, 0, &y);  // No step: the translations made optimal.
  Eigen::SparseMatrix<double> h;
  Eigen::VectorXd g;
  IsotropicNewtonSystem(p, m, y, &h, &g);
  const Eigen::MatrixXd hd(h);
  // Split into translation (t) and rotation tangent (w) unknowns.
  std::vector<int> t_index, w_index;
  for (int i = 0; i < n - 1; ++i) {
    for (int a = 0; a < d; ++a) t_index.push_back(block * i + a);
    for (int a = 0; a < q; ++a) w_index.push_back(block * i + d + a);
  }
  auto sub = [&](const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd out(rows.size(), cols.size());
    for (size_t r = 0; r < rows.size(); ++r) {
      for (size_t c = 0; c < cols.size(); ++c) out(r, c) = hd(rows[r], cols[c]);
    }
    return out;
  };
  const Eigen::MatrixXd htt = sub(t_index, t_index);
  const Eigen::MatrixXd htw = sub(t_index, w_index);
  const Eigen::MatrixXd reduced =
      sub(w_index, w_index) - htw.transpose() * htt.ldlt().solve(htw);
  const Eigen::MatrixXd s = DenseCertificateMatrix(m, n, d, y.rightCols(d * n));
  std::vector<Eigen::MatrixXd> gens;
  if (d == 2) {
    gens.push_back((Eigen::Matrix2d() << 0, -1, 1, 0).finished());
  } else {
    for (int k = 0; k < 3; ++k) {
      gens.push_back(Skew<double>(Eigen::Vector3d::Unit(k)));
    }
  }
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(q * (n - 1), q * (n - 1));
  for (int k = 0; k < d; ++k) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(d * n, q * (n - 1));
    for (int i = 1; i < n; ++i) {
      for (int a = 0; a < q; ++a) {
        const Eigen::MatrixXd dr = y.middleCols(n + d * i, d) * gens[a];
        c.block(d * i, q * (i - 1) + a, d, 1) = dr.row(k).transpose();
      }
    }
    expected += c.transpose() * s * c;
  }
  EXPECT_LT((reduced - expected).norm(), 1e-8 * expected.norm());
  // Away from a critical point (there S Y^T = 0).
  EXPECT_GT((s * y.rightCols(d * n).transpose()).norm(), 1e-3 * s.norm());
}

TEST(CertificateTest, ReducedNewtonHessianIsTheCertificateMatrix) {
  Graph cycle;
  BuildCycle2(8, 0.05, 0.05, 3, &cycle);
  CheckReducedHessian(cycle);
  Graph helix;
  BuildHelix3(4, 0.05, 4, &helix);
  CheckReducedHessian(helix);
}

TEST(CertificateTest, KnownOptimumCertified2DAnd3D) {
  Graph cycle;
  BuildCycle2(24, 0.02, 0.01, 1, &cycle);
  const CertificateResult c2 = CheckAgainstDense(cycle);
  EXPECT_TRUE(c2.certified);
  EXPECT_GE(c2.lower_bound, c2.objective - 1e-5 * c2.objective);
  Graph helix;
  BuildHelix3(10, 0.02, 2, &helix);
  const CertificateResult c3 = CheckAgainstDense(helix);
  EXPECT_TRUE(c3.certified);
  // Either factorization of K (CHOLMOD supernodal, Eigen simplicial; the
  // default picks one by the factor's density) gives that lambda_min.
  for (double flops_per_entry : {0.0, 1e30}) {
    CertificateOptions forced;
    forced.supernodal_flops_per_entry = flops_per_entry;
    const CertificateResult c = CheckAgainstDense(helix, 0, forced);
    EXPECT_TRUE(c.certified);
    EXPECT_NEAR(c.lambda_min, c3.lambda_min, 1e-9 * c3.objective);
    CertificateResult refined;
    std::string why;
    ASSERT_TRUE(CertifyGraph(helix, forced, &refined, &why)) << why;
    EXPECT_TRUE(refined.certified);
    EXPECT_NEAR(refined.objective, c3.objective, 1e-8 * c3.objective);
  }
  // Either elimination order of the pose graph (AMD, METIS's nested
  // dissection; the default picks by flops) gives the dense solver's
  // lambda_min and the same refined point, in 2D and 3D.
  for (auto ordering : {CertificateOptions::Ordering::kAmd,
                        CertificateOptions::Ordering::kNestedDissection}) {
    CertificateOptions forced;
    forced.ordering = ordering;
    for (const Graph* graph : {&cycle, &helix}) {
      const CertificateResult dense_checked =
          CheckAgainstDense(*graph, 0, forced);
      EXPECT_TRUE(dense_checked.certified);
      CertificateResult refined;
      std::string why;
      ASSERT_TRUE(CertifyGraph(*graph, forced, &refined, &why)) << why;
      EXPECT_TRUE(refined.certified);
      const double objective = graph == &cycle ? c2.objective : c3.objective;
      EXPECT_NEAR(refined.objective, objective, 1e-8 * objective);
    }
  }
  CertificateResult via_graph;
  std::string error;
  ASSERT_TRUE(CertifyGraph(helix, CertificateOptions(), &via_graph, &error));
  EXPECT_TRUE(via_graph.certified);
  EXPECT_NEAR(via_graph.objective, c3.objective, 1e-8 * c3.objective);
}

// The conjugate gradients of the Newton refinement give up after a count of
// work, one factorization's flops in iterations (clamped to [10, 50]), never
// after a time: hand-computed budgets.
TEST(CertificateTest, ConjugateGradientBudgetCountsWork) {
  // sphere2500's Newton factor: 3.97e8 flops, 1.53e6 entries, products of
  // 2.85e6 flops: 3.97e8 / (6.12e6 + 2.85e6) = 44.3 -> 45 iterations.
  EXPECT_EQ(CgBudget(3.97e8, 1.53e6, 2.85e6), 45);
  // A cheap factor (parking-garage's simplicial one, 2.2e7 flops, 4.1e5
  // entries, products 3.6e6): 4.3 -> the floor of 10.
  EXPECT_EQ(CgBudget(2.2e7, 4.1e5, 3.6e6), 10);
  EXPECT_EQ(CgBudget(1e12, 1e3, 1e3), 50);
  EXPECT_EQ(CgBudget(0.0, 0.0, 0.0), 50);
}

// The certificate does not depend on the machine's load: a helix of 300
// poses (refined in 5 Newton steps, the later ones by conjugate gradients),
// certified alone and while two threads spin on the cores, gives
// bit-identical results. With the former cutoff at half a factorization's
// wall time a slowed run could cut CG, factorize again and end at another
// point (this test could then fail, though not reproducibly: the cutoff
// itself now reads no clock, see CgBudget).
TEST(CertificateTest, SameResultUnderLoad) {
  Graph helix;
  BuildHelix3(150, 0.05, 5, &helix);
  auto certify = [&]() {
    CertificateResult result;
    std::string error;
    EXPECT_TRUE(CertifyGraph(helix, CertificateOptions(), &result, &error))
        << error;
    return result;
  };
  const CertificateResult quiet = certify();
  EXPECT_TRUE(quiet.certified);
  EXPECT_GE(quiet.refine_iterations, 2);
  std::atomic<bool> stop{false};
  std::vector<std::thread> load;
  for (int k = 0; k < 2; ++k) {
    load.emplace_back([&stop]() {
      volatile double x = 1.0;
      while (!stop.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
    });
  }
  const CertificateResult loaded = certify();
  stop = true;
  for (std::thread& t : load) t.join();
  EXPECT_EQ(loaded.certified, quiet.certified);
  EXPECT_EQ(loaded.refine_iterations, quiet.refine_iterations);
  EXPECT_EQ(loaded.lambda_min, quiet.lambda_min);
  EXPECT_EQ(loaded.objective, quiet.objective);
  EXPECT_EQ(loaded.suboptimality_bound, quiet.suboptimality_bound);
}

// The cycle with its headings twisted by one extra turn around it (winding
// number 2 instead of 1): LM on the g2o objective stays in that local
// minimum; the certificate fails (lambda_min < 0, matching the dense
// eigensolver); the staircase certifies the relaxation, rounds, and LM from
// the rounded values reaches the global optimum (the untwisted solution).
TEST(CertificateTest, TwistedCycleNotCertifiedThenEscaped) {
  Graph graph;
  const int n = 24;
  BuildCycle2(n, 0.02, 0.01, 7, &graph, false);
  Graph reference;
  BuildCycle2(n, 0.02, 0.01, 7, &reference, false);
  OptimizerOptions options;
  options.verbose = false;
  options.max_iterations = 200;
  Optimize(&reference, options, nullptr);
  const double global_chi2 = reference.Chi2();
  for (int k = 0; k < n; ++k) {
    graph.FindNode(Pose2Key(k))->value[2] += 2 * M_PI * k / n;
  }
  Optimize(&graph, options, nullptr);
  const double local_chi2 = graph.Chi2();
  ASSERT_GT(local_chi2, 10 * global_chi2 + 1.0);
  const CertificateResult local = CheckAgainstDense(graph);
  EXPECT_FALSE(local.certified);
  EXPECT_LT(local.lambda_min, -local.delta);
  CertificateResult global;
  std::string error;
  ASSERT_TRUE(
      SolveIsotropicGlobally(&graph, CertificateOptions(), &global, &error))
      << error;
  EXPECT_TRUE(global.certified);
  EXPECT_LT(global.lower_bound, local.objective);
  Optimize(&graph, options, nullptr);
  EXPECT_NEAR(graph.Chi2(), global_chi2, 1e-6 * global_chi2);
  CertificateResult final_certificate;
  ASSERT_TRUE(
      CertifyGraph(graph, CertificateOptions(), &final_certificate, &error));
  EXPECT_TRUE(final_certificate.certified);
}

// A staircase that ends uncertified (here: no rank above d allowed) still
// rounds its last iterate into the graph and says so, so that the caller
// can run LM from it and keep the lower of the two minima (slam optimize
// --certify does); a failure before the staircase leaves the graph as it
// was.
TEST(CertificateTest, UncertifiedStaircaseStillRoundsItsLastIterate) {
  Graph graph;
  const int n = 24;
  BuildCycle2(n, 0.02, 0.01, 7, &graph, false);
  for (int k = 0; k < n; ++k) {
    graph.FindNode(Pose2Key(k))->value[2] += 2 * M_PI * k / n;
  }
  OptimizerOptions options;
  options.verbose = false;
  options.max_iterations = 200;
  Optimize(&graph, options, nullptr);
  const double local_chi2 = graph.Chi2();
  CertificateOptions no_staircase;
  no_staircase.max_rank_increase = 0;
  CertificateResult result;
  std::string error;
  EXPECT_FALSE(SolveIsotropicGlobally(&graph, no_staircase, &result, &error));
  EXPECT_NE(error.find("uncertified at rank 2"), std::string::npos) << error;
  EXPECT_TRUE(result.rounded_uncertified);
  EXPECT_FALSE(result.certified);
  for (int k = 0; k < n; ++k) {
    for (double v : graph.FindNode(Pose2Key(k))->value) {
      EXPECT_TRUE(std::isfinite(v));
    }
  }
  // The rounded rank-d critical point of the isotropic objective lies in
  // the same (twisted) basin: LM from it returns to the same minimum.
  Optimize(&graph, options, nullptr);
  EXPECT_NEAR(graph.Chi2(), local_chi2, 1e-6 * local_chi2);

  Graph refused;
  BuildCycle2(8, 0.0, 0.0, 1, &refused);
  refused.SetFixed(Pose2Key(0), true);
  refused.SetFixed(Pose2Key(3), true);
  const std::vector<double> before = refused.FindNode(Pose2Key(5))->value;
  EXPECT_FALSE(
      SolveIsotropicGlobally(&refused, CertificateOptions(), &result, &error));
  EXPECT_FALSE(result.rounded_uncertified);
  EXPECT_EQ(refused.FindNode(Pose2Key(5))->value, before);
}

TEST(CertificateTest, RefusesGraphsItDoesNotCover) {
  Graph graph;
  BuildCycle2(8, 0.0, 0.0, 1, &graph);
  graph.SetFixed(Pose2Key(0), true);
  graph.SetFixed(Pose2Key(3), true);
  CertificateResult result;
  std::string error;
  EXPECT_FALSE(CertifyGraph(graph, CertificateOptions(), &result, &error));
  EXPECT_NE(error.find("fixed"), std::string::npos) << error;
}

}  // namespace
}  // namespace slam
