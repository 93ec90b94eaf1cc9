// Tests of the initial-guess methods (core/initialization.h) on small 2D and
// 3D pose graphs with a known answer: noise-free measurements generated from
// a ground truth must be reproduced exactly by every method, whatever the
// starting values; fixed nodes, disconnected components and the `only`
// argument are honoured; with noisy measurements the chordal relaxation is
// far better than odometry on a long loop and leads LM to the optimum.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/manifold.h"
#include "ceres/problem.h"
#include "ceres/solver.h"
#include "core/graph.h"
#include "core/initialization.h"
#include "core/lie.h"
#include "core/optimizer.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

using Rng = ::slam::testing::TestRng;

const std::vector<InitMethod>& AllMethods() {
  static const std::vector<InitMethod> methods = {
      InitMethod::kOdometry, InitMethod::kSpanningTree, InitMethod::kChordal};
  return methods;
}

// ---------------------------------------------------------------------------
// Ground-truth graphs.

using EdgeList = std::vector<std::pair<int64_t, int64_t>>;

// A loop of n poses (ids first..first+n-1) with odometry and loop closures;
// a few edges are stored backwards (j -> i) on purpose.
EdgeList LoopEdges(int64_t first, int n) {
  EdgeList edges;
  for (int k = 0; k + 1 < n; ++k) {
    if (k % 5 == 3) {
      edges.emplace_back(first + k + 1, first + k);  // Backwards.
    } else {
      edges.emplace_back(first + k, first + k + 1);
    }
  }
  edges.emplace_back(first + n - 1, first);
  edges.emplace_back(first, first + n / 2);
  edges.emplace_back(first + 3, first + n - 3);
  edges.emplace_back(first + n / 2 + 2, first + 1);
  return edges;
}

std::map<int64_t, Pose2> Trajectory2(Rng* rng, int64_t first, int n,
                                     const Pose2& origin) {
  std::map<int64_t, Pose2> gt;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    gt[first + k] = origin * Pose2(8.0 * std::cos(a) + rng->Uniform(-0.5, 0.5),
                                   6.0 * std::sin(a) + rng->Uniform(-0.5, 0.5),
                                   a + M_PI / 2 + rng->Uniform(-0.6, 0.6));
  }
  return gt;
}

std::map<int64_t, Pose3> Trajectory3(Rng* rng, int64_t first, int n,
                                     const Pose3& origin) {
  std::map<int64_t, Pose3> gt;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())) *
        Eigen::Quaterniond(Eigen::AngleAxisd(rng->Uniform(-1.0, 1.0),
                                             Eigen::Vector3d::UnitY())) *
        Eigen::Quaterniond(Eigen::AngleAxisd(rng->Uniform(-1.5, 1.5),
                                             Eigen::Vector3d::UnitX()));
    gt[first + k] =
        origin *
        Pose3(Eigen::Vector3d(8.0 * std::cos(a), 6.0 * std::sin(a),
                              2.0 * std::sin(3 * a) + rng->Uniform(-0.3, 0.3)),
              q);
  }
  return gt;
}

Pose2 Noise2(Rng* rng, double sigma_t, double sigma_r) {
  return Pose2(sigma_t * rng->Normal(), sigma_t * rng->Normal(),
               sigma_r * rng->Normal());
}

Pose3 Noise3(Rng* rng, double sigma_t, double sigma_r) {
  return Pose3(
      sigma_t * Eigen::Vector3d(rng->Normal(), rng->Normal(), rng->Normal()),
      QuaternionExp<double>(Eigen::Vector3d(sigma_r * rng->Normal(),
                                            sigma_r * rng->Normal(),
                                            sigma_r * rng->Normal())));
}

// Nodes at the ground truth, one between factor per edge with the exact
// (sigma = 0) or noisy measurement. Information random when exact, matched to
// the noise otherwise.
void AddGraph2(const std::map<int64_t, Pose2>& gt, const EdgeList& edges,
               double sigma_t, double sigma_r, Rng* rng, Graph* graph) {
  for (const auto& [id, pose] : gt) {
    if (!graph->HasNode(Pose2Key(id))) {
      ASSERT_NE(graph->AddNode(Pose2Key(id), Pose2Value(pose)), nullptr);
    }
  }
  for (const auto& [i, j] : edges) {
    Pose2 z = gt.at(i).Inverse() * gt.at(j);
    Eigen::Matrix3d info;
    if (sigma_t > 0.0) {
      z = z * Noise2(rng, sigma_t, sigma_r);
      info = Eigen::Vector3d(1 / (sigma_t * sigma_t), 1 / (sigma_t * sigma_t),
                             1 / (sigma_r * sigma_r))
                 .asDiagonal();
    } else {
      info = rng->SpdMatrix(3);
    }
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z, info, &f, &error))
        << error;
    ASSERT_GE(graph->AddFactor(std::move(f)), 0);
  }
}

void AddGraph3(const std::map<int64_t, Pose3>& gt, const EdgeList& edges,
               double sigma_t, double sigma_r, Rng* rng, Graph* graph) {
  for (const auto& [id, pose] : gt) {
    if (!graph->HasNode(Pose3Key(id))) {
      ASSERT_NE(graph->AddNode(Pose3Key(id), Pose3Value(pose)), nullptr);
    }
  }
  for (const auto& [i, j] : edges) {
    Pose3 z = gt.at(i).Inverse() * gt.at(j);
    Matrix6d info;
    if (sigma_t > 0.0) {
      z = z * Noise3(rng, sigma_t, sigma_r);
      // g2o's rotation error is the quaternion vector, about half the angle.
      const double wt = 1 / (sigma_t * sigma_t);
      const double wr = 4 / (sigma_r * sigma_r);
      info = (Eigen::Matrix<double, 6, 1>() << wt, wt, wt, wr, wr, wr)
                 .finished()
                 .asDiagonal();
    } else {
      info = rng->SpdMatrix(6);
    }
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(j), z, info, &f, &error))
        << error;
    ASSERT_GE(graph->AddFactor(std::move(f)), 0);
  }
}

void SetIdentity(Graph* graph, const Key& key) {
  Node* node = graph->FindNode(key);
  ASSERT_NE(node, nullptr);
  node->value =
      key.kind == NodeKind::kPose2 ? Pose2Value(Pose2()) : Pose3Value(Pose3());
}

// Every pose node of the graph except `keep` set to the identity.
void ResetAllBut(Graph* graph, const std::set<Key>& keep) {
  for (const auto& [key, node] : graph->nodes()) {
    if (keep.count(key) == 0) SetIdentity(graph, key);
  }
}

void ExpectPose2Near(const Graph& graph, int64_t id, const Pose2& expected,
                     double tol, const std::string& what) {
  const Node* node = graph.FindNode(Pose2Key(id));
  ASSERT_NE(node, nullptr);
  const Pose2 got = NodePose2(*node);
  EXPECT_LT((got.t - expected.t).norm(), tol) << what << " node " << id;
  EXPECT_LT(std::abs(NormalizeAngle(got.theta - expected.theta)), tol)
      << what << " node " << id;
  EXPECT_GE(node->value[2], -M_PI);
  EXPECT_LT(node->value[2], M_PI);
}

void ExpectPose3Near(const Graph& graph, int64_t id, const Pose3& expected,
                     double tol, const std::string& what) {
  const Node* node = graph.FindNode(Pose3Key(id));
  ASSERT_NE(node, nullptr);
  const Pose3 got = NodePose3(*node);
  EXPECT_LT((got.t - expected.t).norm(), tol) << what << " node " << id;
  EXPECT_LT(got.q.angularDistance(expected.q), tol) << what << " node " << id;
  EXPECT_NEAR(Eigen::Map<const Eigen::Vector4d>(node->value.data() + 3).norm(),
              1.0, 1e-12);
}

// ---------------------------------------------------------------------------

TEST(InitMethodTest, NamesRoundTrip) {
  for (InitMethod m : {InitMethod::kNone, InitMethod::kOdometry,
                       InitMethod::kSpanningTree, InitMethod::kChordal}) {
    InitMethod parsed = InitMethod::kNone;
    ASSERT_TRUE(ParseInitMethod(InitMethodName(m), &parsed));
    EXPECT_EQ(parsed, m);
  }
  EXPECT_STREQ(InitMethodName(InitMethod::kSpanningTree), "spanning_tree");
  InitMethod parsed;
  EXPECT_FALSE(ParseInitMethod("bfs", &parsed));
  EXPECT_FALSE(ParseInitMethod("", &parsed));
  EXPECT_FALSE(ParseInitMethod("Chordal", &parsed));
}

TEST(Initialization2DTest, NoiseFreeLoopIsRecoveredByEveryMethod) {
  Rng rng(1);
  const auto gt = Trajectory2(&rng, 0, 16, Pose2(3.0, -2.0, 0.7));
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph2(gt, LoopEdges(0, 16), 0.0, 0.0, &rng, &graph);
    ResetAllBut(&graph, {Pose2Key(0)});
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    for (const auto& [id, pose] : gt) {
      ExpectPose2Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
    EXPECT_LT(graph.Chi2(), 1e-15) << InitMethodName(method);
  }
}

TEST(Initialization3DTest, NoiseFreeLoopIsRecoveredByEveryMethod) {
  Rng rng(2);
  const auto gt = Trajectory3(
      &rng, 0, 18, Pose3(Eigen::Vector3d(1, 2, 3), rng.Quaternion()));
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph3(gt, LoopEdges(0, 18), 0.0, 0.0, &rng, &graph);
    ResetAllBut(&graph, {Pose3Key(0)});
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    for (const auto& [id, pose] : gt) {
      ExpectPose3Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
    EXPECT_LT(graph.Chi2(), 1e-15) << InitMethodName(method);
  }
}

TEST(InitializationTest, NoneKeepsValues) {
  Rng rng(3);
  const auto gt = Trajectory2(&rng, 0, 10, Pose2());
  Graph graph;
  AddGraph2(gt, LoopEdges(0, 10), 0.0, 0.0, &rng, &graph);
  ResetAllBut(&graph, {Pose2Key(0), Pose2Key(4)});
  std::string error;
  ASSERT_TRUE(InitializePoses(&graph, InitMethod::kNone, &error));
  for (const auto& [key, node] : graph.nodes()) {
    if (key.id == 0 || key.id == 4) {
      EXPECT_EQ(node->value, Pose2Value(gt.at(key.id)));
    } else {
      EXPECT_EQ(node->value, Pose2Value(Pose2()));
    }
  }
}

TEST(Initialization2DTest, FixedMiddleNodeIsTheAnchor) {
  Rng rng(4);
  const auto gt = Trajectory2(&rng, 0, 16, Pose2(-1.0, 4.0, -2.0));
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph2(gt, LoopEdges(0, 16), 0.0, 0.0, &rng, &graph);
    ResetAllBut(&graph, {Pose2Key(7)});  // Node 0 too starts at identity.
    graph.SetFixed(Pose2Key(7), true);
    const std::vector<double> fixed_value = graph.FindNode(Pose2Key(7))->value;
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    EXPECT_EQ(graph.FindNode(Pose2Key(7))->value, fixed_value);
    for (const auto& [id, pose] : gt) {
      ExpectPose2Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
  }
}

TEST(Initialization3DTest, FixedMiddleNodeIsTheAnchor) {
  Rng rng(5);
  const auto gt = Trajectory3(
      &rng, 0, 14, Pose3(Eigen::Vector3d(0, 0, 1), rng.Quaternion()));
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph3(gt, LoopEdges(0, 14), 0.0, 0.0, &rng, &graph);
    ResetAllBut(&graph, {Pose3Key(6)});
    graph.SetFixed(Pose3Key(6), true);
    const std::vector<double> fixed_value = graph.FindNode(Pose3Key(6))->value;
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    EXPECT_EQ(graph.FindNode(Pose3Key(6))->value, fixed_value);
    for (const auto& [id, pose] : gt) {
      ExpectPose3Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
  }
}

TEST(Initialization2DTest, DisconnectedComponentsKeepTheirOwnAnchor) {
  Rng rng(6);
  const auto gt_a = Trajectory2(&rng, 0, 10, Pose2(1.0, 1.0, 0.3));
  const auto gt_b = Trajectory2(&rng, 20, 12, Pose2(-5.0, 2.0, 2.0));
  // The second component's first node is not at the ground truth: the
  // component is recovered relative to it.
  const Pose2 anchor_b(10.0, -3.0, -1.2);
  const Pose2 isolated(4.0, 5.0, 1.0);
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph2(gt_a, LoopEdges(0, 10), 0.0, 0.0, &rng, &graph);
    AddGraph2(gt_b, LoopEdges(20, 12), 0.0, 0.0, &rng, &graph);
    ASSERT_NE(graph.AddNode(Pose2Key(50), Pose2Value(isolated)), nullptr);
    ResetAllBut(&graph, {Pose2Key(0), Pose2Key(20), Pose2Key(50)});
    graph.FindNode(Pose2Key(20))->value = Pose2Value(anchor_b);
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    for (const auto& [id, pose] : gt_a) {
      ExpectPose2Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
    const Pose2 offset = anchor_b * gt_b.at(20).Inverse();
    for (const auto& [id, pose] : gt_b) {
      ExpectPose2Near(graph, id, offset * pose, 1e-9, InitMethodName(method));
    }
    EXPECT_EQ(graph.FindNode(Pose2Key(50))->value, Pose2Value(isolated));
  }
}

TEST(Initialization3DTest, DisconnectedComponentsKeepTheirOwnAnchor) {
  Rng rng(7);
  const auto gt_a = Trajectory3(&rng, 0, 10, Pose3());
  const auto gt_b = Trajectory3(
      &rng, 100, 9, Pose3(Eigen::Vector3d(5, 5, 5), rng.Quaternion()));
  const Pose3 anchor_b(Eigen::Vector3d(-3, 1, 2), rng.Quaternion());
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph3(gt_a, LoopEdges(0, 10), 0.0, 0.0, &rng, &graph);
    AddGraph3(gt_b, LoopEdges(100, 9), 0.0, 0.0, &rng, &graph);
    ResetAllBut(&graph, {Pose3Key(0), Pose3Key(100)});
    graph.FindNode(Pose3Key(100))->value = Pose3Value(anchor_b);
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error)) << error;
    for (const auto& [id, pose] : gt_a) {
      ExpectPose3Near(graph, id, pose, 1e-9, InitMethodName(method));
    }
    const Pose3 offset = anchor_b * gt_b.at(100).Inverse();
    for (const auto& [id, pose] : gt_b) {
      ExpectPose3Near(graph, id, offset * pose, 1e-9, InitMethodName(method));
    }
  }
}

TEST(Initialization2DTest, OnlyTouchesTheGivenNodes) {
  Rng rng(8);
  const auto gt = Trajectory2(&rng, 0, 16, Pose2(2.0, 0.0, 1.0));
  const std::set<Key> only = {Pose2Key(4), Pose2Key(5), Pose2Key(6),
                              Pose2Key(7), Pose2Key(8)};
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph2(gt, LoopEdges(0, 16), 0.0, 0.0, &rng, &graph);
    for (const Key& k : only) SetIdentity(&graph, k);
    // A node outside `only` with a wrong value (not adjacent to `only`): it
    // must not be written either.
    graph.FindNode(Pose2Key(12))->value = {100.0, 100.0, 1.0};
    std::map<Key, std::vector<double>> before;
    for (const auto& [key, node] : graph.nodes()) before[key] = node->value;
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error, &only)) << error;
    for (const auto& [key, node] : graph.nodes()) {
      if (only.count(key) == 0) {
        EXPECT_EQ(node->value, before[key])
            << InitMethodName(method) << " wrote " << key.ToString();
      } else {
        ExpectPose2Near(graph, key.id, gt.at(key.id), 1e-9,
                        InitMethodName(method));
      }
    }
  }
}

TEST(Initialization3DTest, OnlyTouchesTheGivenNodes) {
  Rng rng(9);
  const auto gt = Trajectory3(&rng, 0, 12, Pose3());
  const std::set<Key> only = {Pose3Key(2), Pose3Key(3), Pose3Key(9)};
  for (InitMethod method : AllMethods()) {
    Graph graph;
    AddGraph3(gt, LoopEdges(0, 12), 0.0, 0.0, &rng, &graph);
    for (const Key& k : only) SetIdentity(&graph, k);
    std::map<Key, std::vector<double>> before;
    for (const auto& [key, node] : graph.nodes()) before[key] = node->value;
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, method, &error, &only)) << error;
    for (const auto& [key, node] : graph.nodes()) {
      if (only.count(key) == 0) {
        EXPECT_EQ(node->value, before[key])
            << InitMethodName(method) << " wrote " << key.ToString();
      } else {
        ExpectPose3Near(graph, key.id, gt.at(key.id), 1e-9,
                        InitMethodName(method));
      }
    }
  }
}

TEST(InitializationTest, RejectsMixedSE2AndSE3) {
  Rng rng(10);
  Graph graph;
  AddGraph2(Trajectory2(&rng, 0, 5, Pose2()), LoopEdges(0, 5), 0.0, 0.0, &rng,
            &graph);
  AddGraph3(Trajectory3(&rng, 0, 5, Pose3()), LoopEdges(0, 5), 0.0, 0.0, &rng,
            &graph);
  std::string error;
  EXPECT_FALSE(InitializePoses(&graph, InitMethod::kChordal, &error));
  EXPECT_NE(error.find("mixes"), std::string::npos) << error;
}

TEST(InitializationTest, PriorsDoNotDisturbTheAnchor) {
  // A prior factor is not a between factor: the anchor is still the first
  // node, and the between factors alone place the others.
  Rng rng(11);
  const auto gt = Trajectory2(&rng, 0, 8, Pose2(1, 2, 3));
  Graph graph;
  AddGraph2(gt, LoopEdges(0, 8), 0.0, 0.0, &rng, &graph);
  Factor prior;
  std::string error;
  ASSERT_TRUE(MakePriorSE2(Pose2Key(3), gt.at(3), Eigen::Matrix3d::Identity(),
                           &prior, &error));
  ASSERT_GE(graph.AddFactor(prior), 0);
  ResetAllBut(&graph, {Pose2Key(0)});
  ASSERT_TRUE(InitializePoses(&graph, InitMethod::kChordal, &error)) << error;
  for (const auto& [id, pose] : gt) ExpectPose2Near(graph, id, pose, 1e-9, "");
}

// The chordal translation stage is documented as linear least squares with
// the rotations held fixed. With exact rotation measurements (so the rotation
// stage returns the true rotations) and noisy translations under anisotropic,
// correlated information, its result must be the minimizer of the graph's own
// chi2 over the translations alone (e_theta = 0 there, so chi2 reduces to
// sum e_t^T Omega_tt e_t with e_t in the frame of X_i Z_ij).
template <int kDim>
void ExpectChordalTranslationsAreLeastSquares(unsigned seed) {
  constexpr bool k3d = kDim == 3;
  const int n = 14;
  const auto build = [&](Graph* graph) {
    Rng rng(seed);
    const EdgeList edges = LoopEdges(0, n);
    if (k3d) {
      const auto gt = Trajectory3(&rng, 0, n, Pose3());
      AddGraph3(gt, {}, 0.0, 0.0, &rng, graph);
      for (const auto& [i, j] : edges) {
        Pose3 z = gt.at(i).Inverse() * gt.at(j);
        z.t += 0.3 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
        Matrix6d info = Matrix6d::Zero();
        const Eigen::Matrix3d r = rng.Quaternion().toRotationMatrix();
        info.topLeftCorner<3, 3>() =
            r * Eigen::Vector3d(400.0, 20.0, 1.0).asDiagonal() * r.transpose();
        info.bottomRightCorner<3, 3>() = 100.0 * Eigen::Matrix3d::Identity();
        Factor f;
        std::string error;
        ASSERT_TRUE(
            MakeBetweenSE3(Pose3Key(i), Pose3Key(j), z, info, &f, &error));
        ASSERT_GE(graph->AddFactor(std::move(f)), 0);
      }
    } else {
      const auto gt = Trajectory2(&rng, 0, n, Pose2(1.0, 2.0, 0.5));
      AddGraph2(gt, {}, 0.0, 0.0, &rng, graph);
      for (const auto& [i, j] : edges) {
        Pose2 z = gt.at(i).Inverse() * gt.at(j);
        z.t += 0.3 * Eigen::Vector2d(rng.Normal(), rng.Normal());
        Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
        const Eigen::Matrix2d r =
            Eigen::Rotation2Dd(rng.Uniform(-M_PI, M_PI)).toRotationMatrix();
        info.topLeftCorner<2, 2>() =
            r * Eigen::Vector2d(400.0, 1.0).asDiagonal() * r.transpose();
        info(2, 2) = 100.0;
        Factor f;
        std::string error;
        ASSERT_TRUE(
            MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z, info, &f, &error));
        ASSERT_GE(graph->AddFactor(std::move(f)), 0);
      }
    }
  };
  const Key first = k3d ? Pose3Key(0) : Pose2Key(0);

  Graph chordal;
  build(&chordal);
  std::map<Key, std::vector<double>> truth;
  for (const auto& [key, node] : chordal.nodes()) truth[key] = node->value;
  ResetAllBut(&chordal, {first});
  std::string error;
  ASSERT_TRUE(InitializePoses(&chordal, InitMethod::kChordal, &error)) << error;

  // Reference: the same graph at the true rotations, translations optimized
  // alone (rotation coordinates held by a SubsetManifold), first node fixed.
  Graph reference;
  build(&reference);
  ceres::Problem problem(Graph::ProblemOptions());
  const std::vector<int> rotation_coords =
      k3d ? std::vector<int>{3, 4, 5, 6} : std::vector<int>{2};
  ceres::SubsetManifold hold_rotation(k3d ? 7 : 3, rotation_coords);
  for (const auto& [key, node] : reference.nodes()) {
    problem.AddParameterBlock(node->value.data(),
                              static_cast<int>(node->value.size()),
                              &hold_rotation);
  }
  for (const auto& [id, f] : reference.factors()) {
    problem.AddResidualBlock(f.cost.get(), nullptr,
                             reference.ParameterBlocks(f));
  }
  problem.SetParameterBlockConstant(reference.FindNode(first)->value.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

  for (const auto& [key, node] : chordal.nodes()) {
    const Node* ref = reference.FindNode(key);
    if (k3d) {
      // Rotations: exact.
      EXPECT_LT(NodePose3(*node).q.angularDistance(NodePose3(*ref).q), 1e-9);
    } else {
      EXPECT_LT(std::abs(NormalizeAngle(node->value[2] - ref->value[2])), 1e-9);
    }
    for (int c = 0; c < kDim; ++c) {
      EXPECT_NEAR(node->value[c], ref->value[c], 1e-6)
          << key.ToString() << " coordinate " << c;
    }
  }
  EXPECT_NEAR(chordal.Chi2(), reference.Chi2(), 1e-9 * reference.Chi2());
}

TEST(Initialization2DTest, ChordalTranslationsAreWeightedLeastSquares) {
  ExpectChordalTranslationsAreLeastSquares<2>(21);
}

TEST(Initialization3DTest, ChordalTranslationsAreWeightedLeastSquares) {
  ExpectChordalTranslationsAreLeastSquares<3>(22);
}

// ---------------------------------------------------------------------------
// Noisy measurements.

OptimizerOptions TightOptions() {
  OptimizerOptions options;
  options.max_iterations = 200;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.verbose = false;
  return options;
}

// The 3D chordal initialization ends with Gauss-Newton on the rotations
// alone under each measurement's full rotation information (RefineRotations
// in core/initialization.cc); the relaxation by itself weighs measurements
// isotropically. Two conflicting small-angle measurements of one relative
// rotation, each precise about different axes: the initializer must land on
// the optimizer's answer (translations decouple here: zero measured
// translation), which the plain mean (isotropic weighting) misses.
TEST(Initialization3DTest, ChordalRotationsFollowAnisotropicInformation) {
  for (unsigned seed = 31; seed < 37; ++seed) {
    Rng rng(seed);
    const auto build = [&rng](Graph* graph, Eigen::Vector3d* plain_mean) {
      ASSERT_NE(graph->AddNode(Pose3Key(0), Pose3Value(Pose3())), nullptr);
      ASSERT_NE(graph->AddNode(Pose3Key(1), Pose3Value(Pose3())), nullptr);
      plain_mean->setZero();
      for (int e = 0; e < 2; ++e) {
        const Eigen::Vector3d theta =
            0.05 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
        *plain_mean += 0.5 * theta;
        const Eigen::Matrix3d r = rng.Quaternion().toRotationMatrix();
        Matrix6d info = Matrix6d::Identity();
        info.bottomRightCorner<3, 3>() =
            r * Eigen::Vector3d(1e4, 1e2, 1.0).asDiagonal() * r.transpose();
        Factor f;
        std::string error;
        ASSERT_TRUE(MakeBetweenSE3(
            Pose3Key(0), Pose3Key(1),
            Pose3(Eigen::Vector3d::Zero(), QuaternionExp<double>(theta)), info,
            &f, &error))
            << error;
        ASSERT_GE(graph->AddFactor(std::move(f)), 0);
      }
    };
    Graph graph;
    Eigen::Vector3d plain_mean = Eigen::Vector3d::Zero();
    build(&graph, &plain_mean);
    std::string error;
    ASSERT_TRUE(InitializePoses(&graph, InitMethod::kChordal, &error)) << error;
    const Eigen::Vector3d initial =
        QuaternionLog<double>(NodePose3(*graph.FindNode(Pose3Key(1))).q);
    OptimizerOptions options = TightOptions();
    const OptimizerSummary summary = Optimize(&graph, options, nullptr);
    ASSERT_TRUE(summary.usable) << summary.termination;
    const Eigen::Vector3d optimum =
        QuaternionLog<double>(NodePose3(*graph.FindNode(Pose3Key(1))).q);
    // Not exact: two iterations, and the refinement's error is Log(R_e)
    // where the factor's is the quaternion vector part (equal to O(angle^3)).
    const double plain_mean_error = (plain_mean - optimum).norm();
    EXPECT_LT((initial - optimum).norm(), 0.02 * plain_mean_error)
        << "seed " << seed << ": initial " << initial.transpose()
        << ", optimum " << optimum.transpose();
    EXPECT_GT(plain_mean_error, 0.01) << "seed " << seed;
  }
}

// Two laps of a circle (second lap revisits the first: loop closures), the
// kind of long loop where odometry drifts.
std::map<int64_t, Pose2> TwoLaps2(int per_lap) {
  std::map<int64_t, Pose2> gt;
  for (int k = 0; k < 2 * per_lap; ++k) {
    const double a = 2.0 * M_PI * k / per_lap;
    gt[k] = Pose2(20.0 * std::cos(a), 20.0 * std::sin(a) + 0.02 * (k / per_lap),
                  a + M_PI / 2);
  }
  return gt;
}

EdgeList TwoLapEdges(int per_lap) {
  EdgeList edges;
  for (int k = 0; k + 1 < 2 * per_lap; ++k) edges.emplace_back(k, k + 1);
  for (int k = 0; k < per_lap; k += 5) edges.emplace_back(k, k + per_lap);
  edges.emplace_back(2 * per_lap - 1, 0);
  return edges;
}

std::map<int64_t, Pose3> TwoLaps3(int per_lap) {
  std::map<int64_t, Pose3> gt;
  for (int k = 0; k < 2 * per_lap; ++k) {
    const double a = 2.0 * M_PI * k / per_lap;
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(
            Eigen::AngleAxisd(a + M_PI / 2, Eigen::Vector3d::UnitZ())) *
        Eigen::Quaterniond(
            Eigen::AngleAxisd(0.3 * std::sin(2 * a), Eigen::Vector3d::UnitX()));
    gt[k] = Pose3(Eigen::Vector3d(20.0 * std::cos(a), 20.0 * std::sin(a),
                                  3.0 * std::sin(a) + 0.05 * (k / per_lap)),
                  q);
  }
  return gt;
}

struct NoisyResult {
  double odometry_chi2 = 0.0;
  double chordal_chi2 = 0.0;
  double from_chordal_chi2 = 0.0;
  double reference_chi2 = 0.0;
};

template <typename AddGraphFn>
NoisyResult RunNoisy(const AddGraphFn& add_graph, const Key& first) {
  NoisyResult result;
  std::string error;
  // Reference: LM from the ground truth.
  {
    Graph graph;
    add_graph(&graph);
    const OptimizerSummary s = Optimize(&graph, TightOptions(), nullptr);
    EXPECT_TRUE(s.usable) << s.termination;
    result.reference_chi2 = s.final_chi2;
  }
  {
    Graph graph;
    add_graph(&graph);
    ResetAllBut(&graph, {first});
    EXPECT_TRUE(InitializePoses(&graph, InitMethod::kOdometry, &error))
        << error;
    result.odometry_chi2 = graph.Chi2();
  }
  {
    Graph graph;
    add_graph(&graph);
    ResetAllBut(&graph, {first});
    EXPECT_TRUE(InitializePoses(&graph, InitMethod::kChordal, &error)) << error;
    result.chordal_chi2 = graph.Chi2();
    const OptimizerSummary s = Optimize(&graph, TightOptions(), nullptr);
    EXPECT_TRUE(s.usable) << s.termination;
    result.from_chordal_chi2 = s.final_chi2;
  }
  return result;
}

TEST(Initialization2DTest, NoisyLongLoopChordalBeatsOdometry) {
  const int per_lap = 150;
  const auto gt = TwoLaps2(per_lap);
  const EdgeList edges = TwoLapEdges(per_lap);
  const auto add_graph = [&](Graph* graph) {
    Rng rng(12);  // Same noise for every copy of the graph.
    AddGraph2(gt, edges, 0.05, 0.02, &rng, graph);
  };
  const NoisyResult r = RunNoisy(add_graph, Pose2Key(0));
  RecordProperty("odometry_chi2", std::to_string(r.odometry_chi2));
  RecordProperty("chordal_chi2", std::to_string(r.chordal_chi2));
  EXPECT_LT(r.chordal_chi2, 0.02 * r.odometry_chi2)
      << "chordal " << r.chordal_chi2 << " odometry " << r.odometry_chi2;
  EXPECT_NEAR(r.from_chordal_chi2, r.reference_chi2, 1e-9 * r.reference_chi2);
  // The optimum is about the number of redundant measurement dofs.
  const double redundant = 3.0 * edges.size() - 3.0 * (gt.size() - 1);
  EXPECT_GT(r.reference_chi2, 0.3 * redundant);
  EXPECT_LT(r.reference_chi2, 3.0 * redundant);
}

TEST(Initialization3DTest, NoisyLongLoopChordalBeatsOdometry) {
  const int per_lap = 100;
  const auto gt = TwoLaps3(per_lap);
  const EdgeList edges = TwoLapEdges(per_lap);
  const auto add_graph = [&](Graph* graph) {
    Rng rng(13);
    AddGraph3(gt, edges, 0.05, 0.02, &rng, graph);
  };
  const NoisyResult r = RunNoisy(add_graph, Pose3Key(0));
  EXPECT_LT(r.chordal_chi2, 0.02 * r.odometry_chi2)
      << "chordal " << r.chordal_chi2 << " odometry " << r.odometry_chi2;
  EXPECT_NEAR(r.from_chordal_chi2, r.reference_chi2, 1e-9 * r.reference_chi2);
}

// The two linear backends of the chordal initialization (Eigen's simplicial
// LDL^T with int indices, CHOLMOD's supernodal LL^T with 64-bit indices, the
// one large graphs take) solve the same systems: on a noisy graph, where the
// relaxation's answer is not the ground truth, they must agree to rounding.
// Conjugate gradients (the backend of graphs whose factor does not fit),
// run to a relative residual of 1e-12, agree with them to 1e-8.
template <typename AddGraphFn>
void ExpectBackendsAgree(const AddGraphFn& add_graph, const Key& first,
                         LinearBackend other = LinearBackend::kSupernodal,
                         double tolerance = 1e-9) {
  std::vector<std::vector<double>> values[2];
  const LinearBackend backends[2] = {LinearBackend::kSimplicial, other};
  for (int b = 0; b < 2; ++b) {
    Graph graph;
    add_graph(&graph);
    ResetAllBut(&graph, {first});
    InitOptions options;
    options.backend = backends[b];
    options.iterative_tolerance = 1e-12;
    std::string error;
    InitReport report;
    ASSERT_TRUE(InitializePoses(&graph, InitMethod::kChordal, &error, nullptr,
                                options, &report))
        << error;
    EXPECT_EQ(report.backend, backends[b]);
    if (backends[b] == LinearBackend::kIterative) {
      EXPECT_GT(report.iterative_iterations, 0);
      EXPECT_LT(report.iterative_error, 1e-12);
    }
    for (const auto& [key, node] : graph.nodes()) {
      values[b].push_back(node->value);
    }
  }
  ASSERT_EQ(values[0].size(), values[1].size());
  double max_diff = 0.0;
  for (size_t i = 0; i < values[0].size(); ++i) {
    for (size_t k = 0; k < values[0][i].size(); ++k) {
      max_diff =
          std::max(max_diff, std::abs(values[0][i][k] - values[1][i][k]));
    }
  }
  EXPECT_LT(max_diff, tolerance) << LinearBackendName(other);
  // The answer is not the starting point: the backends did the solving.
  Graph reset;
  add_graph(&reset);
  ResetAllBut(&reset, {first});
  double moved = 0.0;
  size_t i = 0;
  for (const auto& [key, node] : reset.nodes()) {
    for (size_t k = 0; k < node->value.size(); ++k) {
      moved = std::max(moved, std::abs(node->value[k] - values[1][i][k]));
    }
    ++i;
  }
  EXPECT_GT(moved, 1.0);
}

TEST(Initialization2DTest, LinearBackendsAgree) {
  const auto gt = TwoLaps2(150);
  const auto add_graph = [&](Graph* graph) {
    Rng rng(14);
    AddGraph2(gt, TwoLapEdges(150), 0.05, 0.02, &rng, graph);
  };
  ExpectBackendsAgree(add_graph, Pose2Key(0));
  ExpectBackendsAgree(add_graph, Pose2Key(0), LinearBackend::kIterative, 1e-8);
}

TEST(Initialization3DTest, LinearBackendsAgree) {
  const auto gt = TwoLaps3(100);
  const auto add_graph = [&](Graph* graph) {
    Rng rng(15);
    AddGraph3(gt, TwoLapEdges(100), 0.05, 0.02, &rng, graph);
  };
  ExpectBackendsAgree(add_graph, Pose3Key(0));
  ExpectBackendsAgree(add_graph, Pose3Key(0), LinearBackend::kIterative, 1e-8);
}

// A factor larger than the memory or costlier than the flops allowed stops
// the initialization with a message giving its size, before anything is
// allocated or written, when the conjugate-gradient fallback is off; with it
// (the default) the same graph is solved by conjugate gradients.
TEST(InitializationTest, FactorLargerThanAllowedIsAClearError) {
  const auto gt = TwoLaps3(100);
  Graph graph;
  Rng rng(16);
  AddGraph3(gt, TwoLapEdges(100), 0.05, 0.02, &rng, &graph);
  ResetAllBut(&graph, {Pose3Key(0)});
  std::map<Key, std::vector<double>> before;
  for (const auto& [key, node] : graph.nodes()) before[key] = node->value;
  InitOptions options;
  options.iterative_fallback = false;
  options.max_factor_bytes = 1000.0;
  std::string error;
  EXPECT_FALSE(
      InitializePoses(&graph, InitMethod::kChordal, &error, nullptr, options));
  EXPECT_NE(error.find("nonzeros"), std::string::npos) << error;
  for (const auto& [key, node] : graph.nodes()) {
    EXPECT_EQ(node->value, before.at(key));
  }
  // The same for a factorization costing more flops than allowed.
  options.max_factor_bytes = 1e9;
  options.max_factor_flops = 1000.0;
  error.clear();
  EXPECT_FALSE(
      InitializePoses(&graph, InitMethod::kChordal, &error, nullptr, options));
  EXPECT_NE(error.find("flops"), std::string::npos) << error;
  for (const auto& [key, node] : graph.nodes()) {
    EXPECT_EQ(node->value, before.at(key));
  }
  // The fallback: conjugate gradients, the same answer as the direct
  // solve that has room for the factor.
  Graph direct;
  for (const auto& [key, node] : graph.nodes()) {
    direct.AddNode(key, node->value);
  }
  for (const auto& [id, factor] : graph.factors()) direct.AddFactor(factor);
  options.iterative_fallback = true;
  options.iterative_tolerance = 1e-12;
  InitReport report;
  ASSERT_TRUE(InitializePoses(&graph, InitMethod::kChordal, &error, nullptr,
                              options, &report))
      << error;
  EXPECT_EQ(report.backend, LinearBackend::kIterative);
  // With room for it the same graph initializes directly.
  options = InitOptions();
  ASSERT_TRUE(InitializePoses(&direct, InitMethod::kChordal, &error, nullptr,
                              options, &report))
      << error;
  EXPECT_NE(report.backend, LinearBackend::kIterative);
  double max_diff = 0.0;
  for (const auto& [key, node] : graph.nodes()) {
    const std::vector<double>& v = direct.FindNode(key)->value;
    for (size_t k = 0; k < v.size(); ++k) {
      max_diff = std::max(max_diff, std::abs(node->value[k] - v[k]));
    }
  }
  EXPECT_LT(max_diff, 1e-8);
}

}  // namespace
}  // namespace slam
