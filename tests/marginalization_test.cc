// Marginalization (core/marginalization.h) and its prior
// (factors/marginalization_prior.h):
//   * on a linear problem the prior reproduces the full problem's estimate
//     and marginal covariance of the kept states to numerical precision;
//   * on a nonlinear SE(3) pose graph, marginalising at the batch optimum and
//     re-solving gives the batch estimate and covariance; marginalising at a
//     perturbed point agrees to first order (error shrinks quadratically);
//   * the prior's Jacobian against numeric differentiation (GradientChecker
//     with the manifolds), away from the linearization point;
//   * FEJ: J0 and x0 stay fixed while the values move;
//   * robust kernels enter the linearization as Ceres' corrector does.
#include "core/marginalization.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ceres/ceres.h"
#include "ceres/gradient_checker.h"
#include "core/graph.h"
#include "core/manifolds.h"
#include "core/marginals.h"
#include "core/optimizer.h"
#include "factors/marginalization_prior.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_linear_cost.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using testing::LinearCost;
using testing::TestRng;

Eigen::MatrixXd RandomMatrix(TestRng* rng, int rows, int cols) {
  Eigen::MatrixXd m(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m(r, c) = rng->Normal();
  }
  return m;
}

void AddLinear(Graph* graph, const std::vector<Key>& keys, TestRng* rng) {
  std::vector<Eigen::MatrixXd> a;
  for (size_t k = 0; k < keys.size(); ++k) a.push_back(RandomMatrix(rng, 3, 3));
  Eigen::VectorXd z(3);
  z << rng->Normal(), rng->Normal(), rng->Normal();
  Factor f;
  f.keys = keys;
  f.cost = std::make_shared<LinearCost>(a, z);
  ASSERT_GE(graph->AddFactor(std::move(f)), 0);
}

// A chain of 3D Euclidean states x0..x(n-1): a unary factor on x0, one on
// x3, linear factors between neighbours and a "loop" from x1 to x(n-1).
void BuildLinearChain(Graph* graph, int n, unsigned seed) {
  TestRng rng(seed);
  for (int i = 0; i < n; ++i) {
    graph->AddNode(Point3Key(i), {rng.Normal(), rng.Normal(), rng.Normal()});
  }
  AddLinear(graph, {Point3Key(0)}, &rng);
  AddLinear(graph, {Point3Key(3)}, &rng);
  for (int i = 0; i + 1 < n; ++i) {
    AddLinear(graph, {Point3Key(i), Point3Key(i + 1)}, &rng);
  }
  AddLinear(graph, {Point3Key(1), Point3Key(n - 1)}, &rng);
  AddLinear(graph, {Point3Key(0), Point3Key(2)}, &rng);
}

OptimizerOptions Quiet() {
  OptimizerOptions o;
  o.verbose = false;
  o.function_tolerance = 1e-14;
  o.gradient_tolerance = 1e-14;
  o.parameter_tolerance = 1e-14;
  return o;
}

TEST(MarginalizationTest, LinearProblemMatchesFullEstimateAndCovariance) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    constexpr int kN = 8;
    Graph full, window;
    BuildLinearChain(&full, kN, seed);
    BuildLinearChain(&window, kN, seed);
    Optimize(&full, Quiet(), nullptr);
    std::vector<Key> kept;
    for (int i = 3; i < kN; ++i) kept.push_back(Point3Key(i));
    std::map<Key, Eigen::MatrixXd> cov_full, cov_window;
    std::string error;
    ASSERT_TRUE(ComputeMarginals(&full, kept, &cov_full, &error)) << error;

    // Marginalise x0, x1, x2 at the (arbitrary) initial values: the problem
    // is linear, so the linearization point does not matter.
    FactorId prior_id = -1;
    ASSERT_TRUE(MarginalizeNodes(
        &window, {Point3Key(0), Point3Key(1), Point3Key(2)},
        MarginalizationOptions(), MakeMarginalizationPrior, &prior_id, &error))
        << error;
    ASSERT_GE(prior_id, 0);
    EXPECT_EQ(window.NumNodes(), static_cast<size_t>(kN - 3));
    const Factor* prior = window.FindFactor(prior_id);
    EXPECT_EQ(prior->type, FactorType::kMarginalizationPrior);
    // x1 reached x(n-1), x2 reached x3: the prior touches x3 and x(n-1).
    ASSERT_EQ(prior->keys.size(), 2u);
    EXPECT_EQ(prior->keys[0], Point3Key(3));
    EXPECT_EQ(prior->keys[1], Point3Key(kN - 1));

    Optimize(&window, Quiet(), nullptr);
    ASSERT_TRUE(ComputeMarginals(&window, kept, &cov_window, &error)) << error;
    for (const Key& key : kept) {
      const std::vector<double>& a = full.FindNode(key)->value;
      const std::vector<double>& b = window.FindNode(key)->value;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], 1e-8) << key.ToString();
      EXPECT_LT((cov_full[key] - cov_window[key]).norm(),
                1e-8 * cov_full[key].norm())
          << key.ToString();
    }
  }
}

// An SE(3) chain with odometry, a loop closure and a prior on the first pose;
// measurements with noise of std `noise` (0: consistent measurements).
void BuildPoseGraph(Graph* graph, int n, unsigned seed, double noise = 0.05) {
  TestRng rng(seed);
  // One draw per statement: the order in which a compiler evaluates
  // function arguments is unspecified (gcc right to left, clang left to
  // right), and the graph must be the same under both (the sanitizer build
  // uses clang). The order below is the one gcc used.
  auto normal3 = [&rng]() {
    const double z = rng.Normal();
    const double y = rng.Normal();
    const double x = rng.Normal();
    return Eigen::Vector3d(x, y, z);
  };
  std::vector<Pose3> truth;
  Pose3 x;
  for (int i = 0; i < n; ++i) {
    truth.push_back(x);
    const Eigen::Vector3d w =
        Eigen::Vector3d(0.05, 0.05, 0.4) + 0.05 * normal3();
    const double tz = 0.1 * rng.Normal();
    const double ty = 0.2 * rng.Normal();
    x = x * Pose3(Eigen::Vector3d(1.0, ty, tz), QuaternionExp<double>(w));
  }
  auto noisy = [&](const Pose3& p, double s) {
    const Eigen::Vector3d dq = s * normal3();
    const Eigen::Vector3d dt = s * normal3();
    return Pose3(p.t + dt, p.q * QuaternionExp<double>(dq));
  };
  for (int i = 0; i < n; ++i) {
    graph->AddNode(Pose3Key(i), Pose3Value(noisy(truth[i], 0.1)));
  }
  const Eigen::Matrix<double, 6, 6> info =
      100.0 * Eigen::Matrix<double, 6, 6>::Identity();
  std::string error;
  Factor f;
  ASSERT_TRUE(MakePriorSE3(Pose3Key(0), truth[0], info, &f, &error));
  graph->AddFactor(std::move(f));
  for (int i = 0; i + 1 < n; ++i) {
    Factor b;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(i + 1),
                               noisy(truth[i].Inverse() * truth[i + 1], noise),
                               info, &b, &error));
    graph->AddFactor(std::move(b));
  }
  for (int i = 0; i + 4 < n; i += 3) {
    Factor b;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(i + 4),
                               noisy(truth[i].Inverse() * truth[i + 4], noise),
                               info, &b, &error));
    graph->AddFactor(std::move(b));
  }
}

// Max difference between the kept poses of two graphs (tangent norm).
double MaxPoseDifference(const Graph& a, const Graph& b,
                         const std::vector<Key>& keys) {
  const SE3Manifold se3;
  double worst = 0.0;
  for (const Key& key : keys) {
    Eigen::Matrix<double, 6, 1> d;
    se3.Minus(a.FindNode(key)->value.data(), b.FindNode(key)->value.data(),
              d.data());
    worst = std::max(worst, d.norm());
  }
  return worst;
}

TEST(MarginalizationTest, NonlinearPoseGraphMatchesBatch) {
  constexpr int kN = 12;
  Graph full;
  BuildPoseGraph(&full, kN, 3);
  Optimize(&full, Quiet(), nullptr);
  std::vector<Key> marg, kept;
  for (int i = 0; i < 5; ++i) marg.push_back(Pose3Key(i));
  for (int i = 5; i < kN; ++i) kept.push_back(Pose3Key(i));
  std::map<Key, Eigen::MatrixXd> cov_full;
  std::string error;
  ASSERT_TRUE(ComputeMarginals(&full, kept, &cov_full, &error)) << error;

  // Linearised at the batch optimum: the same optimum and covariance.
  {
    Graph window;
    BuildPoseGraph(&window, kN, 3);
    for (const auto& [key, node] : full.nodes()) {
      std::copy(node->value.begin(), node->value.end(),
                window.FindNode(key)->value.begin());
    }
    ASSERT_TRUE(MarginalizeNodes(&window, marg, MarginalizationOptions(),
                                 MakeMarginalizationPrior, nullptr, &error))
        << error;
    Optimize(&window, Quiet(), nullptr);
    EXPECT_LT(MaxPoseDifference(full, window, kept), 1e-7);
    std::map<Key, Eigen::MatrixXd> cov_window;
    ASSERT_TRUE(ComputeMarginals(&window, kept, &cov_window, &error)) << error;
    for (const Key& key : kept) {
      EXPECT_LT((cov_full[key] - cov_window[key]).norm(),
                1e-6 * cov_full[key].norm());
    }
  }
  // Linearised at the optimum perturbed by s. Marginalization keeps the
  // Gauss-Newton Hessian J^T J, which lacks the sum r_i Hess(r_i) of the
  // exact one: with noisy measurements (r != 0 at the optimum) the error of
  // the re-solved estimate is first order in s (times |r|); with consistent
  // measurements it is second order (shrinks ~100x when s shrinks 10x).
  for (double noise : {0.05, 0.0}) {
    Graph batch;
    BuildPoseGraph(&batch, kN, 3, noise);
    Optimize(&batch, Quiet(), nullptr);
    std::vector<double> errors;
    for (double s : {1e-2, 1e-3}) {
      Graph window;
      BuildPoseGraph(&window, kN, 3, noise);
      TestRng rng(11);
      const SE3Manifold se3;
      for (const auto& [key, node] : batch.nodes()) {
        Eigen::Matrix<double, 6, 1> d;
        for (int c = 0; c < 6; ++c) d[c] = s * rng.Normal();
        se3.Plus(node->value.data(), d.data(),
                 window.FindNode(key)->value.data());
      }
      ASSERT_TRUE(MarginalizeNodes(&window, marg, MarginalizationOptions(),
                                   MakeMarginalizationPrior, nullptr, &error))
          << error;
      Optimize(&window, Quiet(), nullptr);
      errors.push_back(MaxPoseDifference(batch, window, kept));
    }
    EXPECT_LT(errors[0], 1e-2);
    if (noise == 0.0) {
      EXPECT_LT(errors[1], errors[0] / 30.0)
          << "s=1e-2: " << errors[0] << ", s=1e-3: " << errors[1];
    } else {
      EXPECT_LT(errors[1], errors[0] / 5.0)
          << "s=1e-2: " << errors[0] << ", s=1e-3: " << errors[1];
    }
  }
}

// A prior over a pose and a Euclidean block, from a real marginalization.
LinearPrior PriorOverPoseAndPoint(unsigned seed) {
  TestRng rng(seed);
  Graph graph;
  graph.AddNode(Pose3Key(0), Pose3Value(rng.RandomPose3(3.0)));
  graph.AddNode(Pose3Key(1), Pose3Value(rng.RandomPose3(3.0)));
  graph.AddNode(Point3Key(0), {rng.Normal(), rng.Normal(), rng.Normal()});
  std::string error;
  Factor f;
  EXPECT_TRUE(MakePriorSE3(Pose3Key(0), rng.RandomPose3(3.0),
                           rng.ScaledInformation(6), &f, &error));
  graph.AddFactor(std::move(f));
  EXPECT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), rng.RandomPose3(3.0),
                             rng.ScaledInformation(6), &f, &error));
  graph.AddFactor(std::move(f));
  Factor l;
  l.keys = {Pose3Key(0), Point3Key(0)};
  std::vector<Eigen::MatrixXd> a = {RandomMatrix(&rng, 3, 7),
                                    RandomMatrix(&rng, 3, 3)};
  l.cost = std::make_shared<LinearCost>(a, Eigen::Vector3d(1, 2, 3));
  graph.AddFactor(std::move(l));
  LinearPrior prior;
  std::vector<FactorId> used;
  EXPECT_TRUE(ComputeMarginalizationPrior(
      graph, {Pose3Key(0)}, MarginalizationOptions(), &prior, &used, &error));
  EXPECT_EQ(used.size(), 3u);
  return prior;
}

TEST(MarginalizationPriorTest, JacobiansMatchNumericInTangentSpace) {
  const SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3, nullptr};
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const LinearPrior prior = PriorOverPoseAndPoint(seed);
    ASSERT_EQ(prior.keys.size(), 2u);
    ASSERT_EQ(prior.keys[0], Pose3Key(1));  // Key order: pose3 before point3.
    ASSERT_EQ(prior.j0.rows(), 9);
    std::unique_ptr<ceres::CostFunction> cost(
        MarginalizationPriorCost::Create(prior));
    TestRng rng(100 + seed);
    // Away from x0: a pose moved by up to ~0.5 rad, a point by ~1.
    std::vector<double> pose(7), point(3);
    Eigen::Matrix<double, 6, 1> d;
    for (int c = 0; c < 6; ++c) d[c] = 0.3 * rng.Normal();
    se3.Plus(prior.x0[0].data(), d.data(), pose.data());
    for (int c = 0; c < 3; ++c) point[c] = prior.x0[1][c] + rng.Normal();
    ceres::NumericDiffOptions numeric;
    ceres::GradientChecker checker(cost.get(), &manifolds, numeric);
    ceres::GradientChecker::ProbeResults results;
    const double* params[2] = {pose.data(), point.data()};
    EXPECT_TRUE(checker.Probe(params, 1e-6, &results)) << results.error_log;
    // At x0 the residual is r0 and the tangent Jacobian is J0.
    Eigen::VectorXd r(9);
    const double* at_x0[2] = {prior.x0[0].data(), prior.x0[1].data()};
    ASSERT_TRUE(cost->Evaluate(at_x0, r.data(), nullptr));
    EXPECT_LT((r - prior.r0).norm(), 1e-12);
    // J0^T J0 = H*, J0^T r0 = b*.
    EXPECT_LT((prior.j0.transpose() * prior.j0 - prior.hessian).norm(),
              1e-9 * prior.hessian.norm());
    EXPECT_LT((prior.j0.transpose() * prior.r0 - prior.gradient).norm(),
              1e-9 * (1.0 + prior.gradient.norm()));
  }
}

TEST(MarginalizationPriorTest, FirstEstimateJacobiansStayFixed) {
  // Marginalise x0 of the linear chain, then move the kept values (as a
  // window re-solve would) and check that the prior keeps J0 and x0.
  Graph window;
  BuildLinearChain(&window, 6, 9);
  FactorId id = -1;
  std::string error;
  ASSERT_TRUE(MarginalizeNodes(&window, {Point3Key(0)},
                               MarginalizationOptions(),
                               MakeMarginalizationPrior, &id, &error));
  const auto* cost = dynamic_cast<const MarginalizationPriorCost*>(
      window.FindFactor(id)->cost.get());
  ASSERT_NE(cost, nullptr);
  const LinearPrior before = cost->prior();
  Optimize(&window, Quiet(), nullptr);
  TestRng rng(4);
  for (const auto& [key, node] : window.nodes()) {
    for (double& v : node->value) v += rng.Normal();
  }
  const LinearPrior& after = cost->prior();
  EXPECT_EQ((after.j0 - before.j0).norm(), 0.0);
  for (size_t k = 0; k < before.x0.size(); ++k) {
    EXPECT_EQ(after.x0[k], before.x0[k]);
  }
  // Euclidean blocks: the evaluated Jacobian is J0 wherever the values are,
  // while a fresh linearization at the moved values is a different prior.
  const Factor& factor = *window.FindFactor(id);
  std::vector<const double*> params =
      static_cast<const Graph&>(window).ParameterBlocks(factor);
  const int rows = cost->num_residuals();
  Eigen::VectorXd r(rows);
  std::vector<
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
      jac(params.size());
  std::vector<double*> jac_ptrs;
  for (auto& j : jac) {
    j.resize(rows, 3);
    jac_ptrs.push_back(j.data());
  }
  ASSERT_TRUE(cost->Evaluate(params.data(), r.data(), jac_ptrs.data()));
  for (size_t k = 0; k < jac.size(); ++k) {
    EXPECT_EQ((jac[k] - before.j0.middleCols(3 * k, 3)).norm(), 0.0);
  }
}

// Gauss-Newton Hessian of a whole graph over its free nodes' tangents, every
// factor linearised at `points` (current values for nodes not listed).
Eigen::MatrixXd TotalHessian(const Graph& graph,
                             const LinearizationPoints& points) {
  using RowMajor =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  std::map<Key, int> offset;
  int n = 0;
  for (const auto& [key, node] : graph.nodes()) {
    offset[key] = n;
    n += NodeTangentSize(*node);
  }
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [id, factor] : graph.factors()) {
    const int rows = factor.cost->num_residuals();
    std::vector<const double*> params;
    for (const Key& key : factor.keys) {
      auto it = points.find(key);
      params.push_back(it != points.end() ? it->second.data()
                                          : graph.FindNode(key)->value.data());
    }
    std::vector<RowMajor> ambient(factor.keys.size());
    std::vector<double*> ptrs;
    for (size_t k = 0; k < factor.keys.size(); ++k) {
      ambient[k].resize(rows, factor.cost->parameter_block_sizes()[k]);
      ptrs.push_back(ambient[k].data());
    }
    Eigen::VectorXd r(rows);
    EXPECT_TRUE(factor.cost->Evaluate(params.data(), r.data(), ptrs.data()));
    std::vector<Eigen::MatrixXd> tangent;
    for (size_t k = 0; k < factor.keys.size(); ++k) {
      const ceres::Manifold* m = graph.ManifoldFor(factor.keys[k].kind);
      RowMajor plus(m->AmbientSize(), m->TangentSize());
      m->PlusJacobian(params[k], plus.data());
      tangent.push_back(ambient[k] * plus);
    }
    for (size_t a = 0; a < factor.keys.size(); ++a) {
      for (size_t b = 0; b < factor.keys.size(); ++b) {
        h.block(offset[factor.keys[a]], offset[factor.keys[b]], 6, 6) +=
            tangent[a].transpose() * tangent[b];
      }
    }
  }
  return h;
}

// First-estimate Jacobians (core/marginalization.h). A pose graph with no
// prior leaves the global pose unobserved: its Hessian has a 6-dimensional
// null space at any single linearization point. Marginalise three poses one
// after another, moving the remaining estimates between marginalizations (as
// the window's solves do). With the FEJ points kept as the sliding window
// keeps them, the remaining graph (priors and factors) still observes nothing
// of the global pose; linearising each marginalization at the then current
// values instead gains spurious information there.
TEST(MarginalizationTest, FirstEstimateJacobiansKeepTheUnobservedDirections) {
  for (const bool fej : {true, false}) {
    Graph graph;
    BuildPoseGraph(&graph, 9, 17);
    std::vector<FactorId> priors;
    for (const auto& [id, factor] : graph.factors()) {
      if (factor.keys.size() == 1) priors.push_back(id);
    }
    for (FactorId id : priors) graph.RemoveFactor(id);
    LinearizationPoints points;
    TestRng rng(5);
    const SE3Manifold se3;
    for (int m = 0; m < 3; ++m) {
      FactorId prior_id = -1;
      std::string error;
      ASSERT_TRUE(MarginalizeNodes(
          &graph, {Pose3Key(m)}, MarginalizationOptions(),
          MakeMarginalizationPrior, &prior_id, &error, fej ? &points : nullptr))
          << error;
      points.erase(Pose3Key(m));
      for (const Key& key : graph.FindFactor(prior_id)->keys) {
        if (fej && points.count(key) == 0) {
          points[key] = graph.FindNode(key)->value;
        }
      }
      for (const auto& [key, node] : graph.nodes()) {  // A "solve" moves them.
        Eigen::Matrix<double, 6, 1> delta;
        delta << 0.05 * rng.Normal3(), 0.05 * rng.Normal3();
        std::vector<double> moved(7);
        se3.Plus(node->value.data(), delta.data(), moved.data());
        node->value = moved;
      }
    }
    const Eigen::MatrixXd h = TotalHessian(graph, points);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
    const Eigen::VectorXd values = eig.eigenvalues();  // Ascending.
    const double sixth = values[5] / values[values.size() - 1];
    if (fej) {
      EXPECT_LT(sixth, 1e-12) << "eigenvalues " << values.head(8).transpose();
    } else {
      EXPECT_GT(sixth, 1e-6) << "eigenvalues " << values.head(8).transpose();
    }
  }
}

TEST(MarginalizationTest, RobustKernelUsesCeresCorrector) {
  // One factor with a Cauchy kernel on a 2-state problem: the prior's
  // Hessian must equal the Schur complement of the Hessian Ceres builds
  // (its Jacobian evaluation applies the same corrector).
  TestRng rng(21);
  Graph graph;
  graph.AddNode(Point3Key(0), {0.5, -1.0, 2.0});
  graph.AddNode(Point3Key(1), {1.0, 1.0, 1.0});
  Factor f;
  f.keys = {Point3Key(0), Point3Key(1)};
  f.cost = std::make_shared<LinearCost>(
      std::vector<Eigen::MatrixXd>{RandomMatrix(&rng, 3, 3),
                                   RandomMatrix(&rng, 3, 3)},
      Eigen::Vector3d(0.3, 0.2, 0.1));
  f.loss = std::make_shared<ceres::CauchyLoss>(0.5);
  graph.AddFactor(std::move(f));
  Factor u;
  u.keys = {Point3Key(0)};
  u.cost = std::make_shared<LinearCost>(
      std::vector<Eigen::MatrixXd>{RandomMatrix(&rng, 3, 3)},
      Eigen::Vector3d(0.0, 0.0, 0.0));
  graph.AddFactor(std::move(u));

  ceres::Problem problem(Graph::ProblemOptions());
  graph.BuildProblem(&problem);
  ceres::CRSMatrix jacobian;
  double cost = 0.0;
  std::vector<double> gradient;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, &gradient,
                   &jacobian);
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(jacobian.num_rows, 6);
  for (int row = 0; row < jacobian.num_rows; ++row) {
    for (int k = jacobian.rows[row]; k < jacobian.rows[row + 1]; ++k) {
      j(row, jacobian.cols[k]) = jacobian.values[k];
    }
  }
  const Eigen::MatrixXd h = j.transpose() * j;  // Blocks: x0 then x1.
  const Eigen::Map<Eigen::VectorXd> g(gradient.data(), 6);
  const Eigen::MatrixXd expected =
      h.bottomRightCorner(3, 3) - h.bottomLeftCorner(3, 3) *
                                      h.topLeftCorner(3, 3).inverse() *
                                      h.topRightCorner(3, 3);
  const Eigen::VectorXd expected_b =
      g.tail(3) -
      h.bottomLeftCorner(3, 3) * h.topLeftCorner(3, 3).inverse() * g.head(3);
  LinearPrior prior;
  std::vector<FactorId> used;
  std::string error;
  ASSERT_TRUE(ComputeMarginalizationPrior(
      graph, {Point3Key(0)}, MarginalizationOptions(), &prior, &used, &error));
  EXPECT_LT((prior.hessian - expected).norm(), 1e-9 * expected.norm());
  EXPECT_LT((prior.gradient - expected_b).norm(), 1e-9 * expected_b.norm());
}

TEST(MarginalizationTest, RejectsUnknownKeysAndNeedsABuilder) {
  Graph graph;
  BuildLinearChain(&graph, 4, 1);
  std::string error;
  EXPECT_FALSE(MarginalizeNodes(&graph, {Point3Key(42)},
                                MarginalizationOptions(),
                                MakeMarginalizationPrior, nullptr, &error));
  EXPECT_NE(error.find("no such node"), std::string::npos);
  EXPECT_FALSE(MarginalizeNodes(&graph, {Point3Key(0)},
                                MarginalizationOptions(), nullptr, nullptr,
                                &error));
  EXPECT_EQ(graph.NumNodes(), 4u);  // Unchanged on failure.
}

}  // namespace
}  // namespace slam
