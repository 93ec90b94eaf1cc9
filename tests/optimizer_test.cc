// Tests of the batch optimizer (core/optimizer.h) on noisy 2D and 3D pose
// graphs: LM, Gauss-Newton and dogleg reach the same optimum; the gauge rule
// (fixed nodes, else priors, else the first node held constant); the
// summary's chi2 figures equal Graph::Chi2() before and after; chi2 (g2o's
// convention) is twice Ceres' cost; one progress line per iteration.
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/problem.h"
#include "core/conventions.h"
#include "core/graph.h"
#include "core/initialization.h"
#include "core/lie.h"
#include "core/optimizer.h"
#include "factors/pose_factors.h"
#include "factors/robust_kernels.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

using Rng = ::slam::testing::TestRng;

Pose2 Noise2(Rng* rng, double st, double sr) {
  return Pose2(st * rng->Normal(), st * rng->Normal(), sr * rng->Normal());
}

Pose3 Noise3(Rng* rng, double st, double sr) {
  return Pose3(st * rng->Normal3(), QuaternionExp<double>(sr * rng->Normal3()));
}

// A serpentine ("lawn-mower") 2D trajectory of rows x cols poses with
// odometry and loop closures between neighbouring rows; measurements and
// initial values noisy. Information with off-diagonal terms.
struct Graph2Spec {
  int rows = 5;
  int cols = 10;
  double sigma_t = 0.1;
  double sigma_r = 0.03;
  double init_t = 0.3;  // Initial values: ground truth times this noise.
  double init_r = 0.1;
  unsigned seed = 1;
};

std::map<int64_t, Pose2> BuildGraph2(const Graph2Spec& spec, Graph* graph) {
  Rng rng(spec.seed);
  std::map<int64_t, Pose2> gt;
  std::map<std::pair<int, int>, int64_t> id_at;
  int64_t id = 0;
  for (int r = 0; r < spec.rows; ++r) {
    for (int k = 0; k < spec.cols; ++k) {
      const int c = r % 2 == 0 ? k : spec.cols - 1 - k;
      const double heading = r % 2 == 0 ? 0.0 : M_PI;
      gt[id] = Pose2(2.0 * c + 0.2 * rng.Normal(), 2.0 * r + 0.2 * rng.Normal(),
                     heading + 0.1 * rng.Normal());
      id_at[{r, c}] = id;
      ++id;
    }
  }
  for (const auto& [i, pose] : gt) {
    graph->AddNode(Pose2Key(i),
                   Pose2Value(pose * Noise2(&rng, spec.init_t, spec.init_r)));
  }
  Eigen::Matrix3d info;
  info << 1 / (spec.sigma_t * spec.sigma_t),
      0.2 / (spec.sigma_t * spec.sigma_t), 0.0,
      0.2 / (spec.sigma_t * spec.sigma_t), 1 / (spec.sigma_t * spec.sigma_t),
      0.0, 0.0, 0.0, 1 / (spec.sigma_r * spec.sigma_r);
  auto add = [&](int64_t i, int64_t j) {
    const Pose2 z = gt.at(i).Inverse() * gt.at(j) *
                    Noise2(&rng, spec.sigma_t, spec.sigma_r);
    Factor f;
    std::string error;
    EXPECT_TRUE(MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z, info, &f, &error));
    EXPECT_GE(graph->AddFactor(std::move(f)), 0);
  };
  for (int64_t i = 0; i + 1 < id; ++i) add(i, i + 1);
  for (int r = 0; r + 1 < spec.rows; ++r) {
    for (int c = 0; c < spec.cols; c += 2)
      add(id_at[{r, c}], id_at[{r + 1, c}]);
  }
  return gt;
}

// A 3D helix of two turns with loop closures between the turns.
std::map<int64_t, Pose3> BuildGraph3(unsigned seed, int per_turn, Graph* graph,
                                     double init_t = 0.2,
                                     double init_r = 0.05) {
  Rng rng(seed);
  std::map<int64_t, Pose3> gt;
  const int n = 2 * per_turn;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / per_turn;
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(
                                     a + M_PI / 2, Eigen::Vector3d::UnitZ())) *
                                 QuaternionExp<double>(0.2 * rng.Normal3());
    gt[k] = Pose3(Eigen::Vector3d(10 * std::cos(a), 10 * std::sin(a),
                                  0.5 * k / per_turn) +
                      0.1 * rng.Normal3(),
                  q);
  }
  for (const auto& [i, pose] : gt) {
    graph->AddNode(Pose3Key(i),
                   Pose3Value(pose * Noise3(&rng, init_t, init_r)));
  }
  const double st = 0.05, sr = 0.01;
  Matrix6d info = Matrix6d::Zero();
  info.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() / (st * st);
  info(0, 1) = info(1, 0) = 0.3 / (st * st);
  info.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * 4 / (sr * sr);
  auto add = [&](int64_t i, int64_t j) {
    const Pose3 z = gt.at(i).Inverse() * gt.at(j) * Noise3(&rng, st, sr);
    Factor f;
    std::string error;
    EXPECT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(j), z, info, &f, &error));
    EXPECT_GE(graph->AddFactor(std::move(f)), 0);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  for (int k = 0; k < per_turn; k += 3) add(k, k + per_turn);
  return gt;
}

OptimizerOptions Tight(SolverKind kind) {
  OptimizerOptions options;
  options.solver = kind;
  options.max_iterations = 200;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.verbose = false;
  return options;
}

std::map<Key, std::vector<double>> Values(const Graph& graph) {
  std::map<Key, std::vector<double>> values;
  for (const auto& [key, node] : graph.nodes()) values[key] = node->value;
  return values;
}

// Ceres' cost (1/2 sum rho(|r|^2)) of the graph at its current values.
double CeresCost(const Graph& graph, bool use_loss) {
  ceres::Problem problem(Graph::ProblemOptions());
  graph.BuildProblem(&problem, use_loss);
  double cost = 0.0;
  EXPECT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost,
                               nullptr, nullptr, nullptr));
  return cost;
}

// ---------------------------------------------------------------------------

TEST(SolverKindTest, NamesRoundTrip) {
  for (SolverKind k : {SolverKind::kLevenbergMarquardt,
                       SolverKind::kGaussNewton, SolverKind::kDogleg}) {
    SolverKind parsed = SolverKind::kDogleg;
    ASSERT_TRUE(ParseSolverKind(SolverKindName(k), &parsed));
    EXPECT_EQ(parsed, k);
  }
  SolverKind parsed;
  EXPECT_FALSE(ParseSolverKind("levenberg", &parsed));
  EXPECT_FALSE(ParseSolverKind("", &parsed));
}

TEST(OptimizerTest, AllSolversReachTheSameOptimum2D) {
  std::map<SolverKind, double> chi2;
  std::map<SolverKind, std::map<Key, std::vector<double>>> values;
  for (SolverKind kind : {SolverKind::kLevenbergMarquardt,
                          SolverKind::kGaussNewton, SolverKind::kDogleg}) {
    Graph graph;
    BuildGraph2(Graph2Spec(), &graph);
    const double before = graph.Chi2();
    const OptimizerSummary s = Optimize(&graph, Tight(kind), nullptr);
    EXPECT_TRUE(s.usable) << SolverKindName(kind) << ": " << s.termination;
    EXPECT_TRUE(s.converged) << SolverKindName(kind) << ": " << s.termination;
    EXPECT_GT(s.iterations, 0);
    EXPECT_LT(s.final_chi2, 0.01 * before) << SolverKindName(kind);
    chi2[kind] = s.final_chi2;
    values[kind] = Values(graph);
  }
  const double ref = chi2[SolverKind::kLevenbergMarquardt];
  EXPECT_NEAR(chi2[SolverKind::kGaussNewton], ref, 1e-8 * ref);
  EXPECT_NEAR(chi2[SolverKind::kDogleg], ref, 1e-8 * ref);
  for (const auto& [key, v] : values[SolverKind::kLevenbergMarquardt]) {
    for (SolverKind kind : {SolverKind::kGaussNewton, SolverKind::kDogleg}) {
      for (size_t c = 0; c < v.size(); ++c) {
        EXPECT_NEAR(values[kind][key][c], v[c], 1e-6)
            << SolverKindName(kind) << " " << key.ToString();
      }
    }
  }
}

TEST(OptimizerTest, AllSolversReachTheSameOptimum3D) {
  std::map<SolverKind, double> chi2;
  for (SolverKind kind : {SolverKind::kLevenbergMarquardt,
                          SolverKind::kGaussNewton, SolverKind::kDogleg}) {
    Graph graph;
    BuildGraph3(2, 30, &graph);
    const double before = graph.Chi2();
    const OptimizerSummary s = Optimize(&graph, Tight(kind), nullptr);
    EXPECT_TRUE(s.usable) << SolverKindName(kind) << ": " << s.termination;
    EXPECT_TRUE(s.converged) << SolverKindName(kind) << ": " << s.termination;
    EXPECT_LT(s.final_chi2, 0.01 * before) << SolverKindName(kind);
    chi2[kind] = s.final_chi2;
  }
  const double ref = chi2[SolverKind::kLevenbergMarquardt];
  EXPECT_NEAR(chi2[SolverKind::kGaussNewton], ref, 1e-8 * ref);
  EXPECT_NEAR(chi2[SolverKind::kDogleg], ref, 1e-8 * ref);
}

TEST(OptimizerTest, DefaultOptionsConverge) {
  Graph graph;
  BuildGraph2(Graph2Spec(), &graph);
  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary s = Optimize(&graph, options, nullptr);
  EXPECT_TRUE(s.converged) << s.termination;
  Graph reference;
  BuildGraph2(Graph2Spec(), &reference);
  const OptimizerSummary r =
      Optimize(&reference, Tight(SolverKind::kLevenbergMarquardt), nullptr);
  EXPECT_NEAR(s.final_chi2, r.final_chi2, 1e-6 * r.final_chi2);
}

TEST(OptimizerTest, LinearSolversAgree) {
  double ref = -1.0;
  for (const std::string solver : {"auto", "sparse_normal_cholesky", "dense_qr",
                                   "dense_normal_cholesky"}) {
    Graph graph;
    BuildGraph3(3, 20, &graph);
    OptimizerOptions options = Tight(SolverKind::kLevenbergMarquardt);
    options.linear_solver = solver;
    const OptimizerSummary s = Optimize(&graph, options, nullptr);
    ASSERT_TRUE(s.usable) << solver << ": " << s.termination;
    EXPECT_FALSE(s.linear_solver.empty());
    if (ref < 0) ref = s.final_chi2;
    EXPECT_NEAR(s.final_chi2, ref, 1e-8 * ref) << solver;
  }
}

TEST(OptimizerTest, EliminationOrderingsAgree) {
  // Every ordering (with the gauge node held constant, and with fixed nodes)
  // gives the same optimum.
  for (bool with_fixed : {false, true}) {
    double ref = -1.0;
    for (const std::string ordering :
         {"auto", "ceres", "amd", "metis", "nesdis"}) {
      Graph graph;
      BuildGraph3(7, 20, &graph);
      if (with_fixed) graph.SetFixed(Pose3Key(11), true);
      OptimizerOptions options = Tight(SolverKind::kLevenbergMarquardt);
      options.ordering = ordering;
      const OptimizerSummary s = Optimize(&graph, options, nullptr);
      ASSERT_TRUE(s.usable) << ordering << ": " << s.termination;
      if (ref < 0) ref = s.final_chi2;
      EXPECT_NEAR(s.final_chi2, ref, 1e-8 * ref) << ordering;
    }
  }
}

// A sparse factor beyond the memory or flops allowed: "auto" solves by
// conjugate gradients (CGNR) instead, to the same optimum as the factor.
TEST(OptimizerTest, FactorBeyondTheBudgetFallsBackToConjugateGradients) {
  for (int dim : {2, 3}) {
    const auto build = [dim](Graph* graph) {
      if (dim == 2) {
        BuildGraph2(Graph2Spec(), graph);
      } else {
        BuildGraph3(3, 20, graph);
      }
    };
    Graph direct, iterative, refused;
    build(&direct);
    build(&iterative);
    build(&refused);
    OptimizerOptions options;
    options.verbose = false;
    const OptimizerSummary d = Optimize(&direct, options, nullptr);
    ASSERT_TRUE(d.converged) << d.termination;
    EXPECT_EQ(d.linear_solver_reason.find("conjugate"), std::string::npos);
    options.max_factor_flops = 1.0;
    const OptimizerSummary i = Optimize(&iterative, options, nullptr);
    ASSERT_TRUE(i.converged) << i.termination;
    EXPECT_NE(i.linear_solver_reason.find("conjugate gradients"),
              std::string::npos)
        << i.linear_solver_reason;
    EXPECT_EQ(i.linear_solver, "CGNR");
    EXPECT_NEAR(i.final_chi2, d.final_chi2, 1e-6 * d.final_chi2) << dim;
    // Without the fallback the factorization runs all the same.
    options.iterative_fallback = false;
    const OptimizerSummary r = Optimize(&refused, options, nullptr);
    ASSERT_TRUE(r.converged) << r.termination;
    EXPECT_EQ(r.linear_solver_reason.find("conjugate"), std::string::npos);
    EXPECT_NEAR(r.final_chi2, d.final_chi2, 1e-9 * d.final_chi2) << dim;
  }
}

// A 3D graph of n poses with a between factor from every pose to every
// later one: a dense factor of 6n unknowns (about 4n flops per entry).
void BuildComplete3(int n, Graph* graph) {
  Rng rng(3);
  std::vector<Pose3> gt;
  for (int k = 0; k < n; ++k) {
    gt.push_back(Pose3(Eigen::Vector3d(k, 0.1 * k * k, 0.0),
                       QuaternionExp<double>(0.1 * rng.Normal3())));
    graph->AddNode(Pose3Key(k),
                   Pose3Value(gt.back() * Noise3(&rng, 0.1, 0.02)));
  }
  const Matrix6d info = Matrix6d::Identity() * 100.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      Factor f;
      std::string error;
      ASSERT_TRUE(
          MakeBetweenSE3(Pose3Key(i), Pose3Key(j),
                         gt[i].Inverse() * gt[j] * Noise3(&rng, 0.01, 0.002),
                         info, &f, &error))
          << error;
      ASSERT_GE(graph->AddFactor(std::move(f)), 0);
    }
  }
}

// "auto" picks the sparse library by the ordering analysis' flops per factor
// entry: Eigen's simplicial LDL^T up to 150 (with Ceres' ordering), above it
// CHOLMOD with the least-fill ordering of AMD, METIS and NESDIS. Every
// choice reaches the optimum the other library reaches.
TEST(OptimizerTest, AutoSparseLibraryFollowsTheFactorDensity) {
  struct Case {
    const char* name;
    std::function<void(Graph*)> build;
    const char* library;
    bool searched;  // Ordering other than Ceres' own.
  };
  const std::vector<Case> cases = {
      {"2D lawn-mower", [](Graph* g) { BuildGraph2(Graph2Spec(), g); },
       "eigen_sparse", false},
      {"complete 3D, 12 poses", [](Graph* g) { BuildComplete3(12, g); },
       "eigen_sparse", false},
      {"complete 3D, 60 poses", [](Graph* g) { BuildComplete3(60, g); },
       "suite_sparse", true},
  };
  for (const Case& c : cases) {
    Graph graph, other;
    c.build(&graph);
    c.build(&other);
    OptimizerOptions options;
    options.verbose = false;
    const OptimizerSummary s = Optimize(&graph, options, nullptr);
    ASSERT_TRUE(s.converged) << c.name << ": " << s.termination;
    EXPECT_EQ(s.sparse_library, c.library) << c.name;
    EXPECT_EQ(s.ordering != "ceres", c.searched)
        << c.name << ": " << s.ordering;
    EXPECT_GT(s.factor_flops_per_entry, 0.0) << c.name;
    EXPECT_EQ(s.factor_flops_per_entry > 150.0,
              std::string(c.library) == "suite_sparse")
        << c.name << ": " << s.factor_flops_per_entry;
    options.sparse_library = std::string(c.library) == "eigen_sparse"
                                 ? "suite_sparse"
                                 : "eigen_sparse";
    const OptimizerSummary o = Optimize(&other, options, nullptr);
    ASSERT_TRUE(o.converged) << c.name << ": " << o.termination;
    EXPECT_EQ(o.sparse_library, options.sparse_library);
    EXPECT_NEAR(o.final_chi2, s.final_chi2, 1e-7 * s.final_chi2) << c.name;
  }
}

TEST(OptimizerTest, UnknownLinearSolverIsReported) {
  Graph graph;
  BuildGraph2(Graph2Spec(), &graph);
  const auto before = Values(graph);
  OptimizerOptions options;
  options.verbose = false;
  options.linear_solver = "magic";
  const OptimizerSummary s = Optimize(&graph, options, nullptr);
  EXPECT_FALSE(s.usable);
  EXPECT_FALSE(s.converged);
  EXPECT_NE(s.termination.find("magic"), std::string::npos) << s.termination;
  EXPECT_EQ(Values(graph), before);
}

// ---------------------------------------------------------------------------
// Gauge.

TEST(OptimizerGaugeTest, FirstNodeHeldWhenNothingFixedAndNoPrior) {
  for (SolverKind kind : {SolverKind::kLevenbergMarquardt,
                          SolverKind::kGaussNewton, SolverKind::kDogleg}) {
    {
      Graph graph;
      BuildGraph2(Graph2Spec(), &graph);
      const std::vector<double> first = graph.nodes().begin()->second->value;
      const std::vector<double> other = graph.FindNode(Pose2Key(20))->value;
      const OptimizerSummary s = Optimize(&graph, Tight(kind), nullptr);
      EXPECT_EQ(graph.nodes().begin()->second->value, first);
      EXPECT_NE(graph.FindNode(Pose2Key(20))->value, other);
      EXPECT_NE(s.gauge.find("first node"), std::string::npos) << s.gauge;
      EXPECT_NE(s.gauge.find(Pose2Key(0).ToString()), std::string::npos)
          << s.gauge;
    }
    {
      Graph graph;
      BuildGraph3(4, 15, &graph);
      const std::vector<double> first = graph.FindNode(Pose3Key(0))->value;
      Optimize(&graph, Tight(kind), nullptr);
      EXPECT_EQ(graph.FindNode(Pose3Key(0))->value, first);
    }
  }
}

TEST(OptimizerGaugeTest, FixedNodesAreTheGauge) {
  Graph graph;
  BuildGraph2(Graph2Spec(), &graph);
  graph.SetFixed(Pose2Key(17), true);
  graph.SetFixed(Pose2Key(33), true);
  const auto before = Values(graph);
  const OptimizerSummary s =
      Optimize(&graph, Tight(SolverKind::kLevenbergMarquardt), nullptr);
  EXPECT_TRUE(s.converged) << s.termination;
  EXPECT_EQ(s.gauge, "fixed nodes");
  EXPECT_EQ(graph.FindNode(Pose2Key(17))->value, before.at(Pose2Key(17)));
  EXPECT_EQ(graph.FindNode(Pose2Key(33))->value, before.at(Pose2Key(33)));
  // The first node is free when other nodes are fixed.
  EXPECT_NE(graph.FindNode(Pose2Key(0))->value, before.at(Pose2Key(0)));
}

TEST(OptimizerGaugeTest, PriorsAreTheGauge) {
  Graph graph;
  const auto gt = BuildGraph2(Graph2Spec(), &graph);
  Factor prior;
  std::string error;
  ASSERT_TRUE(MakePriorSE2(Pose2Key(10), gt.at(10),
                           1e4 * Eigen::Matrix3d::Identity(), &prior, &error));
  ASSERT_GE(graph.AddFactor(prior), 0);
  const auto before = Values(graph);
  const OptimizerSummary s =
      Optimize(&graph, Tight(SolverKind::kLevenbergMarquardt), nullptr);
  EXPECT_TRUE(s.converged) << s.termination;
  EXPECT_EQ(s.gauge, "prior factors");
  EXPECT_NE(graph.FindNode(Pose2Key(0))->value, before.at(Pose2Key(0)));
  // Node 10 ends near its prior.
  const Pose2 p10 = NodePose2(*graph.FindNode(Pose2Key(10)));
  EXPECT_LT((p10.t - gt.at(10).t).norm(), 0.05);
}

TEST(OptimizerTest, IsolatedNodeIsLeftAlone) {
  Graph graph;
  BuildGraph2(Graph2Spec(), &graph);
  ASSERT_NE(graph.AddNode(Pose2Key(1000), {1.0, 2.0, 3.0}), nullptr);
  const OptimizerSummary s =
      Optimize(&graph, Tight(SolverKind::kLevenbergMarquardt), nullptr);
  EXPECT_TRUE(s.usable) << s.termination;
  EXPECT_TRUE(s.converged) << s.termination;
  EXPECT_EQ(graph.FindNode(Pose2Key(1000))->value,
            (std::vector<double>{1.0, 2.0, 3.0}));
}

// ---------------------------------------------------------------------------
// chi2 bookkeeping.

TEST(OptimizerChi2Test, SummaryMatchesGraphChi2BeforeAndAfter) {
  for (int dim : {2, 3}) {
    Graph graph;
    if (dim == 2) {
      BuildGraph2(Graph2Spec(), &graph);
    } else {
      BuildGraph3(5, 20, &graph);
    }
    const double before = graph.Chi2();
    const OptimizerSummary s =
        Optimize(&graph, Tight(SolverKind::kLevenbergMarquardt), nullptr);
    EXPECT_DOUBLE_EQ(s.initial_chi2, before);
    EXPECT_DOUBLE_EQ(s.final_chi2, graph.Chi2());
    EXPECT_DOUBLE_EQ(s.initial_robust_chi2, before);  // No kernels.
    EXPECT_DOUBLE_EQ(s.final_robust_chi2, s.final_chi2);
    EXPECT_LT(s.final_chi2, s.initial_chi2);
  }
}

TEST(OptimizerChi2Test, Chi2IsTwiceCeresCost) {
  Graph graph;
  BuildGraph3(6, 20, &graph);
  EXPECT_NEAR(graph.Chi2(), CeresCostToChi2(CeresCost(graph, false)),
              1e-12 * graph.Chi2());
  EXPECT_NEAR(graph.Chi2(), 2.0 * CeresCost(graph, true), 1e-12 * graph.Chi2());
  // With robust kernels: RobustChi2 is twice Ceres' robust cost, Chi2 twice
  // the plain one.
  RobustKernelSpec spec;
  std::string error;
  ASSERT_TRUE(ParseRobustKernel("cauchy:2", &spec, &error));
  Graph robust;
  BuildGraph2(Graph2Spec(), &robust);
  std::vector<FactorId> ids;
  for (const auto& [id, f] : robust.factors()) ids.push_back(id);
  for (FactorId id : ids) {
    Factor f = *robust.FindFactor(id);
    f.loss = MakeLoss(spec);
    robust.RemoveFactor(id);
    ASSERT_GE(robust.AddFactor(f), 0);
  }
  EXPECT_NEAR(robust.RobustChi2(), 2.0 * CeresCost(robust, true),
              1e-12 * robust.RobustChi2());
  EXPECT_NEAR(robust.Chi2(), 2.0 * CeresCost(robust, false),
              1e-12 * robust.Chi2());
  EXPECT_LT(robust.RobustChi2(), robust.Chi2());
  const double before_robust = robust.RobustChi2();
  const OptimizerSummary s =
      Optimize(&robust, Tight(SolverKind::kLevenbergMarquardt), nullptr);
  EXPECT_DOUBLE_EQ(s.initial_robust_chi2, before_robust);
  EXPECT_DOUBLE_EQ(s.final_robust_chi2, robust.RobustChi2());
  EXPECT_DOUBLE_EQ(s.final_chi2, robust.Chi2());
  EXPECT_LT(s.final_robust_chi2, s.initial_robust_chi2);
}

TEST(OptimizerChi2Test, RobustKernelDownweightsAnOutlier) {
  const Graph2Spec spec;
  double plain_error = 0.0, robust_error = 0.0;
  for (bool use_kernel : {false, true}) {
    Graph graph;
    const auto gt = BuildGraph2(spec, &graph);
    // A wrong loop closure between far-apart nodes.
    Factor outlier;
    std::string error;
    Eigen::Matrix3d info = Eigen::Vector3d(100, 100, 1000).asDiagonal();
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(2), Pose2Key(45), Pose2(0.5, 0.0, 0.0),
                               info, &outlier, &error));
    if (use_kernel) {
      RobustKernelSpec k;
      ASSERT_TRUE(ParseRobustKernel("dcs:1", &k, &error));
      outlier.loss = MakeLoss(k);
    }
    ASSERT_GE(graph.AddFactor(outlier), 0);
    Optimize(&graph, Tight(SolverKind::kLevenbergMarquardt), nullptr);
    // Error of the trajectory against the ground truth (relative to node 0).
    const Pose2 g0 = gt.at(0), e0 = NodePose2(*graph.FindNode(Pose2Key(0)));
    double sum = 0.0;
    for (const auto& [id, pose] : gt) {
      const Pose2 est = NodePose2(*graph.FindNode(Pose2Key(id)));
      sum += ((e0.Inverse() * est).t - (g0.Inverse() * pose).t).squaredNorm();
    }
    (use_kernel ? robust_error : plain_error) = std::sqrt(sum / gt.size());
  }
  EXPECT_LT(robust_error, 0.2 * plain_error)
      << "robust " << robust_error << " plain " << plain_error;
}

// ---------------------------------------------------------------------------
// Progress output.

TEST(OptimizerProgressTest, OneLinePerIterationAndSummary) {
  Graph graph;
  BuildGraph2(Graph2Spec(), &graph);
  OptimizerOptions options = Tight(SolverKind::kLevenbergMarquardt);
  options.verbose = true;
  std::ostringstream out;
  const OptimizerSummary s = Optimize(&graph, options, &out);
  std::istringstream lines(out.str());
  std::string line;
  int iteration_lines = 0, done_lines = 0;
  double first_chi2 = -1.0;
  while (std::getline(lines, line)) {
    int iter = -1;
    double chi2 = 0.0;
    if (std::sscanf(line.c_str(), "iter %d chi2 %lf", &iter, &chi2) == 2) {
      EXPECT_EQ(iter, iteration_lines);
      if (iteration_lines == 0) first_chi2 = chi2;
      ++iteration_lines;
    } else if (line.rfind("done:", 0) == 0) {
      ++done_lines;
    }
  }
  EXPECT_EQ(iteration_lines, s.iterations + 1) << out.str();
  EXPECT_EQ(done_lines, 1) << out.str();
  // The printed chi2 is g2o's (no 1/2).
  EXPECT_NEAR(first_chi2, s.initial_chi2, 1e-8 * s.initial_chi2);

  // verbose = false prints nothing.
  Graph quiet;
  BuildGraph2(Graph2Spec(), &quiet);
  options.verbose = false;
  std::ostringstream none;
  Optimize(&quiet, options, &none);
  EXPECT_TRUE(none.str().empty()) << none.str();
}

// LM rejects an overshooting first Gauss-Newton step, shrinks its radius by
// orders of magnitude and crawls; plain Gauss-Newton overshoots once and
// converges. Rotation noise of 0.3 rad on every measurement (as Carlone's
// M3500 variants), from the chordal guess: the default reaches the same
// minimum as LM alone in fewer iterations (13, of which 4 rejected LM steps
// and 9 Gauss-Newton steps, against 18).
TEST(OptimizerTest, RejectedFirstStepsFallBackToGaussNewton) {
  Graph2Spec spec;
  spec.rows = 30;
  spec.cols = 30;
  spec.sigma_r = 0.3;
  spec.seed = 7;
  Graph with_probe;
  BuildGraph2(spec, &with_probe);
  std::string error;
  ASSERT_TRUE(InitializePoses(&with_probe, InitMethod::kChordal, &error))
      << error;
  Graph lm_only;
  for (const auto& [key, node] : with_probe.nodes()) {
    lm_only.AddNode(key, node->value);
  }
  for (const auto& [id, f] : with_probe.factors()) {
    Factor copy = f;
    lm_only.AddFactor(std::move(copy));
  }
  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary fast = Optimize(&with_probe, options, nullptr);
  options.gauss_newton_probe_iterations = 0;
  const OptimizerSummary slow = Optimize(&lm_only, options, nullptr);
  std::printf(
      "probe: %d iterations (%d Gauss-Newton), chi2 %.10g; LM alone: "
      "%d, chi2 %.10g\n",
      fast.iterations, fast.gauss_newton_iterations, fast.final_chi2,
      slow.iterations, slow.final_chi2);
  EXPECT_TRUE(fast.converged) << fast.termination;
  EXPECT_GT(fast.gauss_newton_iterations, 0);
  EXPECT_NEAR(fast.final_chi2, slow.final_chi2, 1e-7 * slow.final_chi2);
  EXPECT_LE(fast.iterations, 14);
  EXPECT_GE(slow.iterations, fast.iterations + 4);
}

}  // namespace
}  // namespace slam
