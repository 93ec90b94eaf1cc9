// Tests of the marginal covariances (core/marginals.h): compared with the
// dense inverse of J^T J, J computed here by numeric differentiation of the
// whitened residuals through the documented tangent (body frame, translation
// first, full-angle rotation) written out independently of the manifolds;
// closed forms for a single prior; the gauge rule; rank-deficient systems
// and absent keys reported with a clear message.
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/graph.h"
#include "core/lie.h"
#include "core/marginals.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

using Rng = ::slam::testing::TestRng;

// The documented tangent, written out here (not through SE2/SE3Manifold):
//   SE(2): (t + R(theta) d_t, theta + d_theta)
//   SE(3): (t + R rho, q * AngleAxis(|phi|, phi / |phi|))
std::vector<double> DocumentedPlus(const Key& key, const std::vector<double>& x,
                                   const Eigen::VectorXd& d) {
  if (key.kind == NodeKind::kPose2) {
    const Eigen::Vector2d t =
        Eigen::Vector2d(x[0], x[1]) +
        Eigen::Rotation2Dd(x[2]).toRotationMatrix() * d.head<2>();
    return {t.x(), t.y(), x[2] + d[2]};
  }
  const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);
  const Eigen::Vector3d t =
      Eigen::Vector3d(x[0], x[1], x[2]) + q.toRotationMatrix() * d.head<3>();
  const Eigen::Vector3d phi = d.tail<3>();
  Eigen::Quaterniond inc = Eigen::Quaterniond::Identity();
  if (phi.norm() > 0) inc = Eigen::AngleAxisd(phi.norm(), phi.normalized());
  const Eigen::Quaterniond out = q * inc;
  return {t.x(), t.y(), t.z(), out.x(), out.y(), out.z(), out.w()};
}

Eigen::VectorXd StackedResiduals(const Graph& graph) {
  std::vector<double> r;
  for (const auto& [id, f] : graph.factors()) {
    const std::vector<const double*> blocks = graph.ParameterBlocks(f);
    Eigen::VectorXd ri(f.cost->num_residuals());
    EXPECT_TRUE(f.cost->Evaluate(blocks.data(), ri.data(), nullptr));
    r.insert(r.end(), ri.data(), ri.data() + ri.size());
  }
  return Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<int>(r.size()));
}

// Dense covariance (J^T J)^-1 over the tangent spaces of the `free` nodes, J
// by central differences of the whitened residuals through DocumentedPlus.
// Returns the per-node diagonal blocks.
std::map<Key, Eigen::MatrixXd> ReferenceMarginals(
    Graph* graph, const std::vector<Key>& free) {
  std::map<Key, int> offset;
  int n = 0;
  for (const Key& k : free) {
    offset[k] = n;
    n += TangentSize(k.kind);
  }
  const int m = static_cast<int>(StackedResiduals(*graph).size());
  Eigen::MatrixXd jac(m, n);
  const double h = 1e-6;
  for (const Key& k : free) {
    Node* node = graph->FindNode(k);
    const std::vector<double> base = node->value;
    const int dim = TangentSize(k.kind);
    for (int c = 0; c < dim; ++c) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(dim);
      d[c] = h;
      node->value = DocumentedPlus(k, base, d);
      const Eigen::VectorXd plus = StackedResiduals(*graph);
      d[c] = -h;
      node->value = DocumentedPlus(k, base, d);
      const Eigen::VectorXd minus = StackedResiduals(*graph);
      jac.col(offset[k] + c) = (plus - minus) / (2 * h);
    }
    node->value = base;
  }
  const Eigen::MatrixXd cov = (jac.transpose() * jac).inverse();
  std::map<Key, Eigen::MatrixXd> blocks;
  for (const Key& k : free) {
    const int dim = TangentSize(k.kind);
    blocks[k] = cov.block(offset[k], offset[k], dim, dim);
  }
  return blocks;
}

double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

// A 2D chain 0..n-1 with one loop closure, not at the optimum (noisy values).
void BuildChain2(Rng* rng, int n, Graph* graph) {
  std::vector<Pose2> gt;
  for (int k = 0; k < n; ++k) {
    gt.emplace_back(1.0 * k, 0.1 * std::sin(k), 0.2 * k);
    const Pose2 noisy =
        gt.back() *
        Pose2(0.05 * rng->Normal(), 0.05 * rng->Normal(), 0.02 * rng->Normal());
    ASSERT_NE(graph->AddNode(Pose2Key(k), Pose2Value(noisy)), nullptr);
  }
  std::string error;
  auto add = [&](int i, int j) {
    Factor f;
    const Pose2 z = gt[i].Inverse() * gt[j];
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z,
                               rng->SpdMatrix(3, 20.0), &f, &error));
    ASSERT_GE(graph->AddFactor(std::move(f)), 0);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  add(0, n - 1);
}

void BuildChain3(Rng* rng, int n, Graph* graph) {
  std::vector<Pose3> gt;
  for (int k = 0; k < n; ++k) {
    gt.emplace_back(Eigen::Vector3d(1.0 * k, 0.3 * k, 0.1 * k * k),
                    rng->Quaternion());
    const Pose3 noisy =
        gt.back() * Pose3(0.05 * rng->Normal3(),
                          QuaternionExp<double>(0.03 * rng->Normal3()));
    ASSERT_NE(graph->AddNode(Pose3Key(k), Pose3Value(noisy)), nullptr);
  }
  std::string error;
  auto add = [&](int i, int j) {
    Factor f;
    const Pose3 z = gt[i].Inverse() * gt[j];
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(j), z,
                               rng->SpdMatrix(6, 20.0), &f, &error));
    ASSERT_GE(graph->AddFactor(std::move(f)), 0);
  };
  for (int k = 0; k + 1 < n; ++k) add(k, k + 1);
  add(1, n - 1);
}

std::vector<Key> Keys(const Graph& graph) {
  std::vector<Key> keys;
  for (const auto& [key, node] : graph.nodes()) keys.push_back(key);
  return keys;
}

// ---------------------------------------------------------------------------

TEST(MarginalsTest, Chain2DWithPriorMatchesDenseInverse) {
  Rng rng(1);
  Graph graph;
  BuildChain2(&rng, 7, &graph);
  Factor prior;
  std::string error;
  ASSERT_TRUE(MakePriorSE2(Pose2Key(0), Pose2(0.1, -0.2, 0.3),
                           rng.SpdMatrix(3, 100.0), &prior, &error));
  ASSERT_GE(graph.AddFactor(prior), 0);
  const std::vector<Key> keys = Keys(graph);
  std::map<Key, Eigen::MatrixXd> cov;
  ASSERT_TRUE(ComputeMarginals(&graph, keys, &cov, &error)) << error;
  const auto ref = ReferenceMarginals(&graph, keys);
  for (const Key& k : keys) {
    ASSERT_EQ(cov.count(k), 1u);
    ASSERT_EQ(cov[k].rows(), 3);
    ASSERT_EQ(cov[k].cols(), 3);
    EXPECT_LT(RelativeDifference(cov[k], ref.at(k)), 1e-6)
        << k.ToString() << "\ngot\n"
        << cov[k] << "\nexpected\n"
        << ref.at(k);
    EXPECT_LT((cov[k] - cov[k].transpose()).norm(), 1e-12 * cov[k].norm());
  }
  // Uncertainty grows along the chain away from the prior (the loop closure
  // to the last node pulls it back a little).
  EXPECT_GT(cov[Pose2Key(3)].trace(), cov[Pose2Key(0)].trace());
}

TEST(MarginalsTest, Chain2DFirstNodeFixedMatchesDenseInverse) {
  for (bool explicitly_fixed : {true, false}) {
    Rng rng(2);
    Graph graph;
    BuildChain2(&rng, 6, &graph);
    // Fixed explicitly, or held by the gauge rule (no fixed node, no prior).
    if (explicitly_fixed) graph.SetFixed(Pose2Key(0), true);
    const std::vector<Key> keys = Keys(graph);
    std::map<Key, Eigen::MatrixXd> cov;
    std::string error;
    ASSERT_TRUE(ComputeMarginals(&graph, keys, &cov, &error)) << error;
    const std::vector<Key> free(keys.begin() + 1, keys.end());
    const auto ref = ReferenceMarginals(&graph, free);
    for (const Key& k : free) {
      EXPECT_LT(RelativeDifference(cov[k], ref.at(k)), 1e-6)
          << k.ToString() << "\ngot\n"
          << cov[k] << "\nexpected\n"
          << ref.at(k);
    }
    // The gauge node has zero covariance.
    EXPECT_EQ(cov[Pose2Key(0)], Eigen::MatrixXd::Zero(3, 3));
  }
}

TEST(MarginalsTest, FixedMiddleNodeIsTheGauge) {
  Rng rng(3);
  Graph graph;
  BuildChain2(&rng, 6, &graph);
  graph.SetFixed(Pose2Key(3), true);
  std::vector<Key> free;
  for (const Key& k : Keys(graph)) {
    if (k != Pose2Key(3)) free.push_back(k);
  }
  std::map<Key, Eigen::MatrixXd> cov;
  std::string error;
  ASSERT_TRUE(ComputeMarginals(&graph, Keys(graph), &cov, &error)) << error;
  const auto ref = ReferenceMarginals(&graph, free);
  for (const Key& k : free) {
    EXPECT_LT(RelativeDifference(cov[k], ref.at(k)), 1e-6) << k.ToString();
  }
  EXPECT_EQ(cov[Pose2Key(3)], Eigen::MatrixXd::Zero(3, 3));
  EXPECT_GT(cov[Pose2Key(0)].trace(), 0.0);
}

TEST(MarginalsTest, Chain3DWithPriorMatchesDenseInverse) {
  Rng rng(4);
  Graph graph;
  BuildChain3(&rng, 6, &graph);
  Factor prior;
  std::string error;
  ASSERT_TRUE(MakePriorSE3(
      Pose3Key(0), Pose3(Eigen::Vector3d(0.1, 0.2, 0.3), rng.Quaternion()),
      rng.SpdMatrix(6, 100.0), &prior, &error));
  ASSERT_GE(graph.AddFactor(prior), 0);
  const std::vector<Key> keys = Keys(graph);
  std::map<Key, Eigen::MatrixXd> cov;
  ASSERT_TRUE(ComputeMarginals(&graph, keys, &cov, &error)) << error;
  const auto ref = ReferenceMarginals(&graph, keys);
  for (const Key& k : keys) {
    ASSERT_EQ(cov[k].rows(), 6);
    ASSERT_EQ(cov[k].cols(), 6);
    EXPECT_LT(RelativeDifference(cov[k], ref.at(k)), 1e-6)
        << k.ToString() << "\ngot\n"
        << cov[k] << "\nexpected\n"
        << ref.at(k);
  }
}

TEST(MarginalsTest, SubsetOfKeys) {
  Rng rng(5);
  Graph graph;
  BuildChain3(&rng, 5, &graph);
  std::map<Key, Eigen::MatrixXd> cov;
  std::string error;
  ASSERT_TRUE(
      ComputeMarginals(&graph, {Pose3Key(2), Pose3Key(4)}, &cov, &error))
      << error;
  EXPECT_EQ(cov.size(), 2u);
  std::vector<Key> free = Keys(graph);
  free.erase(free.begin());  // First node held by the gauge rule.
  const auto ref = ReferenceMarginals(&graph, free);
  EXPECT_LT(RelativeDifference(cov[Pose3Key(2)], ref.at(Pose3Key(2))), 1e-6);
  EXPECT_LT(RelativeDifference(cov[Pose3Key(4)], ref.at(Pose3Key(4))), 1e-6);
}

// Closed forms for one node with one prior at zero error: the covariance in
// the documented tangent is the inverse information with the rotation part
// scaled by 4 (g2o's 3D rotation error is the quaternion vector, half the
// full angle) and no rotation of the translation block (body frame).
TEST(MarginalsTest, SinglePriorClosedForms) {
  Rng rng(6);
  std::string error;
  {
    Graph graph;
    const Pose3 z(Eigen::Vector3d(1, 2, 3), rng.Quaternion());
    ASSERT_NE(graph.AddNode(Pose3Key(0), Pose3Value(z)), nullptr);
    Matrix6d info = Matrix6d::Zero();
    info.topLeftCorner<3, 3>() = Eigen::Vector3d(100.0, 4.0, 1.0).asDiagonal();
    info(0, 1) = info(1, 0) = 10.0;
    info.bottomRightCorner<3, 3>() =
        Eigen::Vector3d(400.0, 25.0, 9.0).asDiagonal();
    Factor prior;
    ASSERT_TRUE(MakePriorSE3(Pose3Key(0), z, info, &prior, &error));
    ASSERT_GE(graph.AddFactor(prior), 0);
    std::map<Key, Eigen::MatrixXd> cov;
    ASSERT_TRUE(ComputeMarginals(&graph, {Pose3Key(0)}, &cov, &error)) << error;
    Matrix6d expected = Matrix6d::Zero();
    expected.topLeftCorner<3, 3>() = info.topLeftCorner<3, 3>().inverse();
    expected.bottomRightCorner<3, 3>() =
        4.0 * info.bottomRightCorner<3, 3>().inverse();
    EXPECT_LT(RelativeDifference(cov[Pose3Key(0)], expected), 1e-9)
        << "\ngot\n"
        << cov[Pose3Key(0)] << "\nexpected\n"
        << expected;
  }
  {
    Graph graph;
    const Pose2 z(1.0, -2.0, 2.5);
    ASSERT_NE(graph.AddNode(Pose2Key(0), Pose2Value(z)), nullptr);
    Eigen::Matrix3d info;
    info << 100, 20, 1, 20, 9, 0.5, 1, 0.5, 50;
    Factor prior;
    ASSERT_TRUE(MakePriorSE2(Pose2Key(0), z, info, &prior, &error));
    ASSERT_GE(graph.AddFactor(prior), 0);
    std::map<Key, Eigen::MatrixXd> cov;
    ASSERT_TRUE(ComputeMarginals(&graph, {Pose2Key(0)}, &cov, &error)) << error;
    const Eigen::Matrix3d expected = info.inverse();
    EXPECT_LT(RelativeDifference(cov[Pose2Key(0)], expected), 1e-9)
        << "\ngot\n"
        << cov[Pose2Key(0)] << "\nexpected\n"
        << expected;
  }
}

TEST(MarginalsTest, EachComponentGetsItsOwnGauge) {
  // Two components, no fixed node and no prior: each component's first node
  // is held constant (Graph::GaugeAnchors), so both have marginals, and
  // those of the second equal the marginals of that component alone.
  Rng rng(7);
  Graph graph;
  BuildChain2(&rng, 4, &graph);
  Graph alone;
  std::string error;
  for (int k = 10; k < 13; ++k) {
    ASSERT_NE(graph.AddNode(Pose2Key(k), {1.0 * k, 0.0, 0.0}), nullptr);
    ASSERT_NE(alone.AddNode(Pose2Key(k), {1.0 * k, 0.0, 0.0}), nullptr);
  }
  for (int k = 10; k < 12; ++k) {
    Factor f;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(k), Pose2Key(k + 1), Pose2(1, 0, 0),
                               Eigen::Matrix3d::Identity(), &f, &error));
    Factor g = f;
    ASSERT_GE(graph.AddFactor(f), 0);
    ASSERT_GE(alone.AddFactor(g), 0);
  }
  const std::vector<Key> anchors = graph.GaugeAnchors();
  ASSERT_EQ(anchors.size(), 2u);
  EXPECT_EQ(anchors[1], Pose2Key(10));
  std::map<Key, Eigen::MatrixXd> cov, cov_alone;
  ASSERT_TRUE(
      ComputeMarginals(&graph, {Pose2Key(11), Pose2Key(2)}, &cov, &error))
      << error;
  ASSERT_TRUE(ComputeMarginals(&alone, {Pose2Key(11)}, &cov_alone, &error))
      << error;
  EXPECT_LT((cov[Pose2Key(11)] - cov_alone[Pose2Key(11)]).norm(), 1e-12);
  EXPECT_GT(cov[Pose2Key(11)].determinant(), 0.0);
  EXPECT_GT(cov[Pose2Key(2)].determinant(), 0.0);
}

TEST(MarginalsTest, IsolatedNodeIsRankDeficient) {
  Rng rng(8);
  Graph graph;
  BuildChain3(&rng, 4, &graph);
  ASSERT_NE(graph.AddNode(Pose3Key(50), Pose3Value(Pose3())), nullptr);
  std::map<Key, Eigen::MatrixXd> cov;
  std::string error;
  // Ceres alone would answer with a zero covariance ("perfectly known").
  EXPECT_FALSE(ComputeMarginals(&graph, {Pose3Key(50)}, &cov, &error));
  EXPECT_NE(error.find(Pose3Key(50).ToString()), std::string::npos) << error;
  EXPECT_NE(error.find("rank deficient"), std::string::npos) << error;
  // Fixed, it is known exactly: zero covariance.
  graph.SetFixed(Pose3Key(50), true);
  graph.SetFixed(Pose3Key(0), true);
  error.clear();
  ASSERT_TRUE(
      ComputeMarginals(&graph, {Pose3Key(50), Pose3Key(2)}, &cov, &error))
      << error;
  EXPECT_EQ(cov[Pose3Key(50)], Eigen::MatrixXd::Zero(6, 6));
  EXPECT_GT(cov[Pose3Key(2)].trace(), 0.0);
}

TEST(MarginalsTest, AbsentKeyIsReported) {
  Rng rng(9);
  Graph graph;
  BuildChain2(&rng, 4, &graph);
  std::map<Key, Eigen::MatrixXd> cov;
  std::string error;
  EXPECT_FALSE(
      ComputeMarginals(&graph, {Pose2Key(1), Pose2Key(77)}, &cov, &error));
  EXPECT_NE(error.find(Pose2Key(77).ToString()), std::string::npos) << error;
}

TEST(MarginalsTest, RepeatedKeyIsAnswered) {
  // Asking for the same node twice (e.g. --marginals 3,3) is not an error.
  Rng rng(10);
  Graph graph;
  BuildChain2(&rng, 5, &graph);
  std::map<Key, Eigen::MatrixXd> once, twice;
  std::string error;
  ASSERT_TRUE(ComputeMarginals(&graph, {Pose2Key(3)}, &once, &error)) << error;
  ASSERT_TRUE(
      ComputeMarginals(&graph, {Pose2Key(3), Pose2Key(3)}, &twice, &error))
      << error;
  EXPECT_LT(RelativeDifference(twice[Pose2Key(3)], once[Pose2Key(3)]), 1e-12);
}

}  // namespace
}  // namespace slam
