// Tests of the g2o reader/writer and the pose-graph format dispatcher
// (datasets/g2o_io.h).
#include "datasets/g2o_io.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/information.h"
#include "core/lie.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::Contains;
using ::slam::testing::DatasetPath;
using ::slam::testing::FixturePath;
using ::slam::testing::ReadText;
using ::slam::testing::TempDir;

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path;
}

uint64_t Bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof(b));
  return b;
}

// Every value, measurement, information entry and fixed flag, bit for bit,
// and the factors in the same order.
void ExpectSameGraph(const Graph& a, const Graph& b) {
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  ASSERT_EQ(a.NumFactors(), b.NumFactors());
  auto na = a.nodes().begin();
  auto nb = b.nodes().begin();
  for (; na != a.nodes().end(); ++na, ++nb) {
    ASSERT_EQ(na->first, nb->first);
    EXPECT_EQ(na->second->fixed, nb->second->fixed) << na->first.ToString();
    ASSERT_EQ(na->second->value.size(), nb->second->value.size());
    for (size_t k = 0; k < na->second->value.size(); ++k) {
      EXPECT_EQ(Bits(na->second->value[k]), Bits(nb->second->value[k]))
          << na->first.ToString() << " value " << k << ": "
          << na->second->value[k] << " vs " << nb->second->value[k];
    }
  }
  auto fa = a.factors().begin();
  auto fb = b.factors().begin();
  for (; fa != a.factors().end(); ++fa, ++fb) {
    const Factor& x = fa->second;
    const Factor& y = fb->second;
    ASSERT_EQ(x.type, y.type);
    ASSERT_EQ(x.keys, y.keys);
    ASSERT_EQ(x.measurement.size(), y.measurement.size());
    for (int k = 0; k < x.measurement.size(); ++k) {
      EXPECT_EQ(Bits(x.measurement[k]), Bits(y.measurement[k]))
          << "factor " << fa->first << " measurement " << k;
    }
    ASSERT_EQ(x.information.rows(), y.information.rows());
    ASSERT_EQ(x.information.cols(), y.information.cols());
    for (int r = 0; r < x.information.rows(); ++r) {
      for (int c = 0; c < x.information.cols(); ++c) {
        EXPECT_EQ(Bits(x.information(r, c)), Bits(y.information(r, c)))
            << "factor " << fa->first << " information " << r << "," << c;
      }
    }
  }
}

bool Read(const std::string& path, Graph* graph, GraphReadReport* report,
          std::string* error, const GraphReadOptions& options = {}) {
  return ReadG2o(path, options, graph, report, error);
}

// Options that skip unknown tags (the fixtures have some), as g2o does.
GraphReadOptions SkipUnknownTags() {
  GraphReadOptions options;
  options.skip_unknown_tags = true;
  return options;
}

// Writes `graph` to dir/name, reads it back and checks both are identical;
// returns the file text.
std::string ExpectRoundTrip(const Graph& graph, const std::string& dir,
                            const std::string& name) {
  const std::string path = dir + "/" + name;
  std::string error;
  EXPECT_TRUE(WriteG2o(path, graph, &error)) << error;
  Graph back;
  GraphReadReport report;
  EXPECT_TRUE(Read(path, &back, &report, &error)) << error;
  ExpectSameGraph(graph, back);
  EXPECT_FALSE(report.initialized_from_edges);
  EXPECT_EQ(report.repaired_information, 0);
  // Writing what was read gives the same file.
  const std::string again = dir + "/again_" + name;
  EXPECT_TRUE(WriteG2o(again, back, &error)) << error;
  EXPECT_EQ(ReadText(path), ReadText(again));
  return ReadText(path);
}

std::vector<const Factor*> Factors(const Graph& graph) {
  std::vector<const Factor*> out;
  for (const auto& [id, f] : graph.factors()) out.push_back(&f);
  return out;
}

const std::vector<double>& Value(const Graph& graph, const Key& key) {
  const Node* node = graph.FindNode(key);
  EXPECT_NE(node, nullptr) << key.ToString();
  static const std::vector<double> kEmpty(7, 0.0);
  return node != nullptr ? node->value : kEmpty;
}

// ---------------------------------------------------------------------------
// Hand-made fixtures.

TEST(G2oIoTest, Reads2dFixtureWithEveryFeature) {
  const std::string path = FixturePath("g2o_2d_features.g2o");
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(path, &graph, &report, &error, SkipUnknownTags())) << error;
  EXPECT_EQ(report.vertices, 4);
  EXPECT_EQ(report.edges, 6);
  EXPECT_EQ(report.fixed, 1);
  EXPECT_EQ(report.repaired_information, 0);
  EXPECT_FALSE(report.initialized_from_edges);
  ASSERT_EQ(report.warnings.size(), 2u);
  EXPECT_EQ(report.warnings[0],
            "unknown tag 'VERTEX_TRACKXY' (2 lines) skipped");
  EXPECT_EQ(report.warnings[1], "unknown tag 'EDGE_SE2_LINE' (1 line) skipped");

  ASSERT_EQ(graph.NumNodes(), 4u);
  ASSERT_EQ(graph.NumFactors(), 6u);
  // FIX before the vertices is applied.
  EXPECT_TRUE(graph.FindNode(Pose2Key(0))->fixed);
  EXPECT_FALSE(graph.FindNode(Pose2Key(1))->fixed);
  EXPECT_EQ(Value(graph, Pose2Key(1)), (std::vector<double>{1.0, 0.1, 0.05}));
  // Tabs; an angle outside [-pi, pi) is wrapped.
  EXPECT_EQ(Value(graph, Pose2Key(2))[0], 2.0);
  EXPECT_DOUBLE_EQ(Value(graph, Pose2Key(2))[2], 4.0 - 2.0 * M_PI);
  // '+' sign, exponent, CRLF line end.
  EXPECT_EQ(Value(graph, Pose2Key(3)), (std::vector<double>{2.5, 1.1, 1.6}));

  const std::vector<const Factor*> f = Factors(graph);
  // File order is kept, the repeated 1-2 edge included.
  EXPECT_EQ(f[0]->keys, (std::vector<Key>{Pose2Key(0), Pose2Key(1)}));
  EXPECT_EQ(f[1]->keys, (std::vector<Key>{Pose2Key(1), Pose2Key(2)}));
  EXPECT_EQ(f[2]->keys, (std::vector<Key>{Pose2Key(1), Pose2Key(2)}));
  EXPECT_EQ(f[3]->keys, (std::vector<Key>{Pose2Key(2), Pose2Key(3)}));
  EXPECT_EQ(f[4]->keys, (std::vector<Key>{Pose2Key(3), Pose2Key(0)}));
  EXPECT_EQ(f[5]->keys, (std::vector<Key>{Pose2Key(1)}));
  for (int k = 0; k < 5; ++k) EXPECT_EQ(f[k]->type, FactorType::kBetweenSE2);
  EXPECT_EQ(f[5]->type, FactorType::kPriorSE2);
  EXPECT_EQ(f[1]->measurement, Eigen::Vector3d(1.01, 0.2, -2.2));
  EXPECT_EQ(f[2]->measurement, Eigen::Vector3d(0.99, 0.21, -2.25));
  // Upper triangle, row-major: I11 I12 I13 I22 I23 I33 = 100 10 5 200 3 50.
  Eigen::Matrix3d expected;
  expected << 100, 10, 5, 10, 200, 3, 5, 3, 50;
  EXPECT_EQ(Eigen::MatrixXd(f[0]->information), Eigen::MatrixXd(expected));
  expected << 30, 1, 2, 1, 30, 3, 2, 3, 30;
  EXPECT_EQ(Eigen::MatrixXd(f[3]->information), Eigen::MatrixXd(expected));
}

TEST(G2oIoTest, RoundTrip2dFixture) {
  Graph graph;
  std::string error;
  ASSERT_TRUE(Read(FixturePath("g2o_2d_features.g2o"), &graph, nullptr, &error,
                   SkipUnknownTags()))
      << error;
  const std::string text = ExpectRoundTrip(graph, TempDir(), "fixture.g2o");
  EXPECT_NE(text.find("FIX 0\n"), std::string::npos);
  EXPECT_NE(text.find("EDGE_PRIOR_SE2 1 "), std::string::npos);
  EXPECT_EQ(text.find("TRACKXY"), std::string::npos);
}

TEST(G2oIoTest, Reads3dFixtureNormalizesQuaternions) {
  const std::string path = FixturePath("g2o_3d_features.g2o");
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(path, &graph, &report, &error)) << error;
  EXPECT_EQ(report.vertices, 4);
  EXPECT_EQ(report.edges, 6);
  EXPECT_EQ(report.fixed, 2);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_TRUE(graph.FindNode(Pose3Key(0))->fixed);
  EXPECT_TRUE(graph.FindNode(Pose3Key(1))->fixed);
  EXPECT_FALSE(graph.FindNode(Pose3Key(2))->fixed);
  // (0, 0, 0, 2) -> identity.
  EXPECT_EQ(Value(graph, Pose3Key(0)),
            (std::vector<double>{0, 0, 0, 0, 0, 0, 1}));
  // (0.1, 0.2, 0.3, 0.9) / |.|.
  const std::vector<double>& v1 = Value(graph, Pose3Key(1));
  const double n = std::sqrt(0.01 + 0.04 + 0.09 + 0.81);
  EXPECT_NEAR(v1[3], 0.1 / n, 1e-15);
  EXPECT_NEAR(v1[6], 0.9 / n, 1e-15);
  for (const auto& [key, node] : graph.nodes()) {
    EXPECT_NEAR(NodePose3(*node).q.squaredNorm(), 1.0, 4e-16);
    const Eigen::Map<const Eigen::Vector4d> q(node->value.data() + 3);
    EXPECT_NEAR(q.squaredNorm(), 1.0, 2e-15) << key.ToString();
  }
  const std::vector<const Factor*> f = Factors(graph);
  ASSERT_EQ(f.size(), 6u);
  for (const Factor* factor : f) {
    EXPECT_NEAR(factor->measurement.tail<4>().squaredNorm(), 1.0, 2e-15);
  }
  EXPECT_EQ(f[1]->keys, f[2]->keys);  // The repeated edge is kept.
  EXPECT_EQ(f[5]->type, FactorType::kPriorSE3);
  // 21 upper-triangle entries, row-major.
  Eigen::Matrix<double, 6, 6> expected;
  expected << 100, 1, 2, 3, 4, 5,  //
      1, 200, 6, 7, 8, 9,          //
      2, 6, 300, 10, 11, 12,       //
      3, 7, 10, 400, 13, 14,       //
      4, 8, 11, 13, 500, 15,       //
      5, 9, 12, 14, 15, 600;
  for (const Factor* factor : f) {
    EXPECT_EQ(Eigen::MatrixXd(factor->information), Eigen::MatrixXd(expected));
  }
}

TEST(G2oIoTest, RoundTrip3dFixture) {
  Graph graph;
  std::string error;
  ASSERT_TRUE(Read(FixturePath("g2o_3d_features.g2o"), &graph, nullptr, &error))
      << error;
  const std::string text = ExpectRoundTrip(graph, TempDir(), "fixture.g2o");
  EXPECT_NE(text.find("FIX 0\nFIX 1\n"), std::string::npos);
  EXPECT_NE(text.find("PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n"), std::string::npos);
  EXPECT_NE(text.find("EDGE_SE3_PRIOR 2 0 "), std::string::npos);
}

// Values that need all 17 digits, signed zeros, subnormals, extremes, angles
// at the ends of [-pi, pi), quaternions normalized in floating point (which
// would not survive a second normalization) and full information matrices.
TEST(G2oIoTest, RoundTripIsBitExactOnRandomGraphs) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> uniform(-1000.0, 1000.0);
  std::normal_distribution<double> normal;
  auto random_information = [&](int n) {
    Eigen::MatrixXd a(n, n);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) a(r, c) = normal(rng);
    }
    Eigen::MatrixXd info =
        a * a.transpose() + Eigen::MatrixXd::Identity(n, n) * 0.1;
    return Eigen::MatrixXd(0.5 * (info + info.transpose()));
  };
  const std::string dir = TempDir();
  for (int dimension : {2, 3}) {
    SCOPED_TRACE(dimension);
    Graph graph;
    const int num_nodes = 60;
    for (int i = 0; i < num_nodes; ++i) {
      std::vector<double> value;
      if (dimension == 2) {
        value = {uniform(rng), uniform(rng),
                 std::uniform_real_distribution<double>(-M_PI, M_PI)(rng)};
      } else {
        Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng),
                             normal(rng));
        q.normalize();
        value = {uniform(rng), uniform(rng), uniform(rng), q.x(),
                 q.y(),        q.z(),        q.w()};
      }
      if (i == 1) value[0] = -0.0;
      if (i == 2) value[0] = 4.9406564584124654e-324;  // Smallest subnormal.
      if (i == 3) value[1] = 1.7976931348623157e308;
      if (i == 4) value[1] = 0.1;
      if (dimension == 2 && i == 5) value[2] = -M_PI;
      if (dimension == 2 && i == 6) value[2] = std::nextafter(M_PI, 0.0);
      ASSERT_NE(graph.AddNode(
                    dimension == 2 ? Pose2Key(i * 7 - 3) : Pose3Key(i * 7 - 3),
                    value),
                nullptr);
      if (i % 9 == 0)
        graph.SetFixed(
            dimension == 2 ? Pose2Key(i * 7 - 3) : Pose3Key(i * 7 - 3), true);
    }
    for (int k = 0; k < 150; ++k) {
      const int i = static_cast<int>(rng() % num_nodes);
      int j = static_cast<int>(rng() % num_nodes);
      if (j == i) j = (i + 1) % num_nodes;
      Factor factor;
      std::string error;
      if (dimension == 2) {
        Pose2 z;
        z.t = Eigen::Vector2d(normal(rng), normal(rng));
        z.theta = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
        const Eigen::Matrix3d info = random_information(3);
        ASSERT_TRUE(
            k % 10 == 9
                ? MakePriorSE2(Pose2Key(i * 7 - 3), z, info, &factor, &error)
                : MakeBetweenSE2(Pose2Key(i * 7 - 3), Pose2Key(j * 7 - 3), z,
                                 info, &factor, &error))
            << error;
      } else {
        Pose3 z;
        z.t = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
        z.q = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng),
                                 normal(rng))
                  .normalized();
        const Eigen::Matrix<double, 6, 6> info = random_information(6);
        ASSERT_TRUE(
            k % 10 == 9
                ? MakePriorSE3(Pose3Key(i * 7 - 3), z, info, &factor, &error)
                : MakeBetweenSE3(Pose3Key(i * 7 - 3), Pose3Key(j * 7 - 3), z,
                                 info, &factor, &error))
            << error;
      }
      ASSERT_GE(graph.AddFactor(std::move(factor)), 0);
    }
    ExpectRoundTrip(graph, dir, "random" + std::to_string(dimension) + ".g2o");
  }
}

TEST(G2oIoTest, InitializesFromEdgesWhenThereAreNoVertices) {
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(FixturePath("g2o_no_vertices.g2o"), &graph, &report, &error))
      << error;
  EXPECT_TRUE(report.initialized_from_edges);
  EXPECT_EQ(report.vertices, 0);
  EXPECT_EQ(report.edges, 5);
  ASSERT_EQ(graph.NumNodes(), 5u);
  ASSERT_EQ(graph.NumFactors(), 5u);
  // The lowest id anchors the chain at the identity; each node composes the
  // first edge that reaches it (the 13-12 edge backwards).
  const Pose2 z0(1.0, 0.0, 0.5), z1(1.0, 0.5, -0.25), z3(-0.8, 0.1, 0.3),
      z4(2.0, -1.0, 3.0);
  const Pose2 x10, x11 = x10 * z0, x12 = x11 * z1, x13 = x12 * z3.Inverse(),
                   x14 = x13 * z4;
  const std::vector<std::pair<int, Pose2>> expected = {
      {10, x10}, {11, x11}, {12, x12}, {13, x13}, {14, x14}};
  for (const auto& [id, x] : expected) {
    const std::vector<double>& v = Value(graph, Pose2Key(id));
    EXPECT_NEAR(v[0], x.t.x(), 1e-12) << id;
    EXPECT_NEAR(v[1], x.t.y(), 1e-12) << id;
    EXPECT_NEAR(NormalizeAngle(v[2] - x.theta), 0.0, 1e-12) << id;
  }
  EXPECT_EQ(Value(graph, Pose2Key(10)), (std::vector<double>{0, 0, 0}));
}

TEST(G2oIoTest, InitializesFromEdgesWhenThereAreNoVertices3d) {
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(
      Read(FixturePath("g2o_3d_no_vertices.g2o"), &graph, &report, &error))
      << error;
  EXPECT_TRUE(report.initialized_from_edges);
  ASSERT_EQ(graph.NumNodes(), 3u);
  const std::vector<const Factor*> f = Factors(graph);
  const Pose3 x1 = MeasurementPose3(*f[0]);
  const Pose3 x2 = x1 * MeasurementPose3(*f[1]).Inverse();
  const Pose3 got1 = NodePose3(*graph.FindNode(Pose3Key(1)));
  const Pose3 got2 = NodePose3(*graph.FindNode(Pose3Key(2)));
  EXPECT_LT((got1.t - x1.t).norm(), 1e-12);
  EXPECT_LT(got1.q.angularDistance(x1.q), 1e-12);
  EXPECT_LT((got2.t - x2.t).norm(), 1e-12);
  EXPECT_LT(got2.q.angularDistance(x2.q), 1e-12);
  EXPECT_NEAR(graph.Chi2(), 0.0, 1e-18);
}

TEST(G2oIoTest, MissingVertexIsAnErrorWhenTheFileHasVertices) {
  const std::string path = FixturePath("g2o_partial_vertices.g2o");
  Graph graph;
  std::string error;
  EXPECT_FALSE(Read(path, &graph, nullptr, &error));
  EXPECT_EQ(error, path + ":5: unknown vertex id 2");
  EXPECT_EQ(graph.NumNodes(), 0u);
}

TEST(G2oIoTest, AllowMissingVerticesInitializesOnlyThose) {
  const std::string path = FixturePath("g2o_partial_vertices.g2o");
  GraphReadOptions options;
  options.allow_missing_vertices = true;
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(path, &graph, &report, &error, options)) << error;
  EXPECT_TRUE(report.initialized_from_edges);
  EXPECT_EQ(report.vertices, 2);
  // The given vertices are kept as they are (not re-derived from edge 0-1).
  EXPECT_EQ(Value(graph, Pose2Key(0)), (std::vector<double>{0.5, -0.5, 0.1}));
  EXPECT_EQ(Value(graph, Pose2Key(1)), (std::vector<double>{1.5, -0.4, 0.2}));
  const Pose2 x2 = Pose2(1.5, -0.4, 0.2) * Pose2(1.0, 0.2, 0.3);
  const std::vector<double>& v = Value(graph, Pose2Key(2));
  EXPECT_NEAR(v[0], x2.t.x(), 1e-12);
  EXPECT_NEAR(v[1], x2.t.y(), 1e-12);
  EXPECT_NEAR(v[2], x2.theta, 1e-12);
}

// ---------------------------------------------------------------------------
// Malformed input.

struct MalformedCase {
  const char* name;
  const char* text;
  int line;
  const char* problem;
};

constexpr char kV2[] = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
constexpr char kV3[] =
    "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n";
constexpr char kInfo21[] = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";

std::vector<MalformedCase> MalformedCases() {
  static const std::string v2 = kV2;
  static const std::string v3 = kV3;
  static const std::vector<std::string> texts = {
      v2 + "EDGE_SE2 0 1 1.2.3 0 0 1 0 0 1 0 1\n",
      v2 + "EDGE_SE2 0 1 abc 0 0 1 0 0 1 0 1\n",
      "# comment\nVERTEX_SE2 0 0 0\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1 7\n",
      v2 + "EDGE_SE2 0 1 nan 0 0 1 0 0 1 0 1\n",
      v2 + "EDGE_SE2 0 1 1 0 0 inf 0 0 1 0 1\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1e999\n",
      v2 + "EDGE_SE2 0 17 1 0 0 1 0 0 1 0 1\n",
      v2 + "\nVERTEX_SE2 1 2 0 0\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 2 0 1 0 1\n",
      v2 + "FIX 0 5\n",
      v2 + "EDGE_SE2 1 1 1 0 0 1 0 0 1 0 1\n",
      v2 + "VERTEX_SE3:QUAT 2 0 0 0 0 0 0 1\n",
      v3 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n",
      "VERTEX_SE2 1.5 0 0 0\n",
      v3 + "VERTEX_SE3:QUAT 2 0 0 0 0 0 0 0\n",
      v3 + "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1" + std::string(kInfo21, 20),
      v3 + "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 "
           "-1 0 0 1 0 1\n",
      v3 +
          "PARAMS_SE3OFFSET 0 0.1 0 0 0 0 0 1\nEDGE_SE3_PRIOR 0 0 0 0 0 0 0 "
          "0 1" +
          kInfo21,
      v2 + "FIX\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 0 1 0x10 0 0 1 0 0 1 0 "
           "1\n",
      v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1 # ok\nEDGE_SE2 0 1 1 0 0 1 0 0 1 "
           "0\n",
      "VERTEX_SE2 0 0 0 0\r\nVERTEX_SE2 0 0 0 0\r\n",
  };
  return {
      {"bad_number", texts[0].c_str(), 3, "bad number '1.2.3' in field 3"},
      {"word", texts[1].c_str(), 3, "bad number 'abc'"},
      {"missing_field", texts[2].c_str(), 2,
       "VERTEX_SE2 needs 4 fields after the tag, found 3 (missing fields)"},
      {"extra_field", texts[3].c_str(), 3,
       "EDGE_SE2 needs 11 fields after the tag, found 12 (extra fields)"},
      {"nan", texts[4].c_str(), 3, "non-finite number 'nan'"},
      {"inf", texts[5].c_str(), 3, "non-finite number 'inf'"},
      {"overflow", texts[6].c_str(), 3, "out-of-range number '1e999'"},
      {"unknown_vertex", texts[7].c_str(), 3, "unknown vertex id 17"},
      {"duplicate_vertex", texts[8].c_str(), 4,
       "duplicate vertex id 1 (first defined at line 2)"},
      {"not_positive_definite", texts[9].c_str(), 3,
       "information matrix is not positive definite"},
      {"indefinite_off_diagonal", texts[10].c_str(), 3,
       "information matrix is not positive definite"},
      {"fix_unknown", texts[11].c_str(), 3, "FIX of unknown vertex id 5"},
      {"self_edge", texts[12].c_str(), 3,
       "self-edge: vertex id 1 is joined to itself"},
      {"mixed_vertices", texts[13].c_str(), 3,
       "the file mixes SE(2) and SE(3) records"},
      {"mixed_edge", texts[14].c_str(), 3,
       "the file mixes SE(2) and SE(3) records"},
      {"bad_id", texts[15].c_str(), 1, "bad vertex id '1.5'"},
      {"zero_quaternion", texts[16].c_str(), 3,
       "quaternion of vertex 2 has zero length"},
      {"missing_information", texts[17].c_str(), 3, "(missing fields)"},
      {"3d_not_positive_definite", texts[18].c_str(), 3,
       "information matrix is not positive definite"},
      {"prior_with_offset", texts[19].c_str(), 4,
       "non-identity PARAMS_SE3OFFSET 0 is not supported"},
      {"empty_fix", texts[20].c_str(), 3, "(missing fields)"},
      {"hex_number", texts[21].c_str(), 4, "bad number '0x10'"},
      {"missing_last_field", texts[22].c_str(), 4, "(missing fields)"},
      {"duplicate_crlf", texts[23].c_str(), 2, "duplicate vertex id 0"},
  };
}

TEST(G2oIoTest, MalformedInputFailsWithFileLineAndProblem) {
  const std::string dir = TempDir();
  for (const MalformedCase& c : MalformedCases()) {
    SCOPED_TRACE(c.name);
    const std::string path = WriteText(dir + "/" + c.name + ".g2o", c.text);
    Graph graph;
    GraphReadReport report;
    std::string error;
    EXPECT_FALSE(Read(path, &graph, &report, &error));
    const std::string prefix = path + ":" + std::to_string(c.line) + ": ";
    EXPECT_EQ(error.substr(0, prefix.size()), prefix) << error;
    EXPECT_NE(error.find(c.problem), std::string::npos) << error;
    EXPECT_EQ(graph.NumNodes(), 0u);
    EXPECT_EQ(graph.NumFactors(), 0u);
  }
}

TEST(G2oIoTest, RepairsInformationWhenAsked) {
  const std::string dir = TempDir();
  const std::string path = WriteText(dir + "/indefinite.g2o",
                                     std::string(kV2) +
                                         "EDGE_SE2 0 1 1 0 0 1 2 0 1 0 1\n"
                                         "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                                         "EDGE_SE2 1 0 1 0 0 1 0 0 0 0 1\n");
  GraphReadOptions options;
  options.repair_information = true;
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(path, &graph, &report, &error, options)) << error;
  EXPECT_EQ(report.repaired_information, 2);
  const std::vector<const Factor*> f = Factors(graph);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_TRUE(IsPositiveDefinite(f[0]->information));
  EXPECT_TRUE(IsPositiveDefinite(f[2]->information));
  EXPECT_EQ(f[1]->information, Eigen::MatrixXd::Identity(3, 3));
  // The repaired matrix is the nearest positive-definite one.
  Eigen::Matrix3d original;
  original << 1, 2, 0, 2, 1, 0, 0, 0, 1;
  EXPECT_LT((f[0]->information - NearestPositiveDefinite(original)).norm(),
            1e-12);
}

TEST(G2oIoTest, MissingFileCannotBeOpened) {
  const std::string path = TempDir() + "/does_not_exist.g2o";
  Graph graph;
  std::string error;
  EXPECT_FALSE(Read(path, &graph, nullptr, &error));
  EXPECT_EQ(error.rfind(path + ": cannot open", 0), 0u) << error;
  // A directory cannot be read either.
  error.clear();
  EXPECT_FALSE(Read(TempDir(), &graph, nullptr, &error));
  EXPECT_NE(error.find(": cannot open"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(ReadPoseGraph(path, {}, &graph, nullptr, &error));
  EXPECT_EQ(error.rfind(path + ": cannot open", 0), 0u) << error;
}

TEST(G2oIoTest, RefusesANonEmptyGraph) {
  Graph graph;
  graph.AddNode(Pose2Key(0), {0, 0, 0});
  std::string error;
  EXPECT_FALSE(Read(FixturePath("g2o_2d_features.g2o"), &graph, nullptr, &error,
                    SkipUnknownTags()));
  EXPECT_NE(error.find("not empty"), std::string::npos) << error;
  EXPECT_EQ(graph.NumNodes(), 1u);
}

TEST(G2oIoTest, UnknownTagsAreWarnedOncePerTagWithACount) {
  std::string text = kV2;
  for (int k = 0; k < 25; ++k) text += "EQUIV 0 1\n";
  text += "VERTEX_LINE 7 1 2\nEQUIV 1 0\n";
  const std::string path = WriteText(TempDir() + "/tags.g2o", text);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(Read(path, &graph, &report, &error, SkipUnknownTags())) << error;
  ASSERT_EQ(report.warnings.size(), 2u);
  EXPECT_EQ(report.warnings[0], "unknown tag 'EQUIV' (26 lines) skipped");
  EXPECT_EQ(report.warnings[1], "unknown tag 'VERTEX_LINE' (1 line) skipped");
  EXPECT_EQ(graph.NumNodes(), 2u);
}

// A misspelt tag must not silently drop its record: by default it is an
// error naming the line and the tag.
TEST(G2oIoTest, UnknownTagIsAnErrorByDefault) {
  const std::string text =
      std::string(kV2) +
      "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE22 1 0 1 0 0 1 0 0 1 0 1\n";
  Graph graph;
  GraphReadReport report;
  std::string error;
  EXPECT_FALSE(ReadG2oFromText("typo.g2o", text, {}, &graph, &report, &error));
  EXPECT_TRUE(Contains(error, "typo.g2o:4: unknown tag 'EDGE_SE22'")) << error;
  EXPECT_EQ(graph.NumNodes(), 0u);
  ASSERT_TRUE(ReadG2oFromText("typo.g2o", text, SkipUnknownTags(), &graph,
                              &report, &error))
      << error;
  EXPECT_EQ(graph.NumFactors(), 1u);
  ASSERT_EQ(report.warnings.size(), 1u);
}

// A file without a single record is not a 0-node graph: nothing to do.
TEST(G2oIoTest, InputWithoutRecordsIsAnError) {
  for (const std::string& text :
       {std::string(), std::string("# only\n\n  # comments\n"),
        std::string("\xEF\xBB\xBF\n")}) {
    Graph graph;
    std::string error;
    EXPECT_FALSE(
        ReadG2oFromText("empty.g2o", text, {}, &graph, nullptr, &error));
    EXPECT_TRUE(Contains(error, "empty.g2o: no records")) << error;
  }
  Graph graph;
  std::string error;
  EXPECT_FALSE(ReadG2o("/dev/null", {}, &graph, nullptr, &error));
  EXPECT_TRUE(Contains(error, "/dev/null: no records")) << error;
  // Only skipped tags: nothing left either.
  EXPECT_FALSE(ReadG2oFromText("tags.g2o", "EQUIV 0 1\n", SkipUnknownTags(),
                               &graph, nullptr, &error));
  EXPECT_TRUE(Contains(error, "no records")) << error;
}

TEST(G2oIoTest, SkipsAUtf8ByteOrderMark) {
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadG2oFromText(
      "bom",
      "\xEF\xBB\xBF" + std::string(kV2) + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n",
      {}, &graph, &report, &error))
      << error;
  EXPECT_EQ(graph.NumNodes(), 2u);
  EXPECT_TRUE(report.warnings.empty());
}

TEST(G2oIoTest, ManyDistinctUnknownTagsAreSummedUp) {
  std::string text;
  for (int k = 0; k < 1000; ++k) text += "TAG" + std::to_string(k) + " 1\n";
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadG2oFromText("tags", text + kV2, SkipUnknownTags(), &graph,
                              &report, &error));
  ASSERT_EQ(report.warnings.size(), 21u);
  EXPECT_EQ(report.warnings.back(), "further unknown tags (980 lines) skipped");
}

// Random damage to valid files must never crash the reader; failures name the
// file and a line.
TEST(G2oIoTest, NeverCrashesOnDamagedInput) {
  std::mt19937 rng(7);
  const std::string alphabet = "0123456789.-+eE #\n\t\rnaifx:_VERTEX";
  int failures = 0, successes = 0;
  for (const char* fixture :
       {"g2o_2d_features.g2o", "g2o_3d_features.g2o", "g2o_no_vertices.g2o"}) {
    const std::string original = ReadText(FixturePath(fixture));
    ASSERT_FALSE(original.empty());
    for (int iteration = 0; iteration < 1500; ++iteration) {
      std::string text = original;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !text.empty(); ++e) {
        const size_t pos = rng() % text.size();
        switch (rng() % 4) {
          case 0:
            text[pos] = alphabet[rng() % alphabet.size()];
            break;
          case 1:
            text.erase(pos, 1 + rng() % 20);
            break;
          case 2:
            text.insert(pos, 1, static_cast<char>(rng() % 256));
            break;
          case 3:
            text.insert(pos, text.substr(rng() % text.size(), rng() % 80));
            break;
        }
      }
      Graph graph;
      GraphReadReport report;
      std::string error;
      if (ReadG2oFromText("damaged.g2o", text, {}, &graph, &report, &error)) {
        ++successes;
        EXPECT_FALSE(std::isnan(graph.Chi2()));
      } else {
        ++failures;
        EXPECT_EQ(error.rfind("damaged.g2o:", 0), 0u) << error;
        EXPECT_EQ(graph.NumNodes(), 0u);
      }
    }
  }
  EXPECT_GT(failures, 100);
  EXPECT_GT(successes, 10);
  // Binary noise.
  for (int iteration = 0; iteration < 200; ++iteration) {
    std::string text(rng() % 2000, '\0');
    for (char& c : text) c = static_cast<char>(rng() % 256);
    Graph graph;
    std::string error;
    ReadG2oFromText("noise", text, {}, &graph, nullptr, &error);
  }
}

// ---------------------------------------------------------------------------
// Writing.

TEST(G2oIoTest, WriteFailureLeavesNoFile) {
  const std::string dir = TempDir();
  Graph graph;
  ASSERT_TRUE(Read(FixturePath("g2o_2d_features.g2o"), &graph, nullptr, nullptr,
                   SkipUnknownTags()));
  WriteText(dir + "/plain_file", "x");
  std::filesystem::create_directory(dir + "/a_directory");
  for (const std::string& path :
       {dir + "/no_such_directory/out.g2o", dir + "/plain_file/out.g2o",
        dir + "/a_directory", std::string("/proc/no_such_dir/x.g2o")}) {
    SCOPED_TRACE(path);
    std::string error;
    EXPECT_FALSE(WriteG2o(path, graph, &error));
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    EXPECT_FALSE(WritePoseGraph(path, graph, &error));
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/no_such_directory"));
  EXPECT_TRUE(std::filesystem::is_directory(dir + "/a_directory"));
  EXPECT_TRUE(std::filesystem::is_empty(dir + "/a_directory"));
  // Nothing but what the test made: no leftover temporary files.
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"a_directory", "plain_file"}));
}

TEST(G2oIoTest, WriteReplacesAnExistingFileAtomically) {
  const std::string dir = TempDir();
  const std::string path = WriteText(dir + "/out.g2o", "old contents\n");
  Graph graph;
  ASSERT_TRUE(Read(FixturePath("g2o_2d_features.g2o"), &graph, nullptr, nullptr,
                   SkipUnknownTags()));
  std::string error;
  ASSERT_TRUE(WriteG2o(path, graph, &error)) << error;
  const std::string text = ReadText(path);
  EXPECT_EQ(text.rfind("VERTEX_SE2 0 0 0 0\n", 0), 0u) << text;
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(G2oIoTest, WriteRejectsWhatCannotBeReadBack) {
  const std::string dir = TempDir();
  std::string error;
  {
    Graph graph;
    graph.AddNode(Pose2Key(0), {0, 0, 0});
    graph.AddNode(Pose3Key(1), {0, 0, 0, 0, 0, 0, 1});
    EXPECT_FALSE(WriteG2o(dir + "/mixed.g2o", graph, &error));
    EXPECT_NE(error.find("both SE(2) and SE(3)"), std::string::npos) << error;
  }
  {
    Graph graph;
    graph.AddNode(Pose2Key(0), {0, std::nan(""), 0});
    EXPECT_FALSE(WriteG2o(dir + "/nan.g2o", graph, &error));
    EXPECT_NE(error.find("non-finite"), std::string::npos) << error;
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  // Nodes that are neither poses nor landmarks are left out.
  Graph graph;
  graph.AddNode(Pose2Key(0), {1, 2, 3});
  graph.AddNode(VelocityKey(0), {4, 5, 6});
  ASSERT_TRUE(WriteG2o(dir + "/points.g2o", graph, &error)) << error;
  EXPECT_EQ(ReadText(dir + "/points.g2o"), "VERTEX_SE2 0 1 2 3\n");
}

// ---------------------------------------------------------------------------
// Dispatcher.

TEST(G2oIoTest, ReadPoseGraphPicksTheReaderByContentThenExtension) {
  const std::string dir = TempDir();
  Graph graph;
  GraphReadReport report;
  std::string error;
  // TORO content in a .g2o file: the content wins.
  const std::string toro =
      WriteText(dir + "/toro_inside.g2o",
                "# comment\nUNKNOWN 1\nVERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n"
                "EDGE2 0 1 1 0 0 1 0 1 1 0 0\n");
  ASSERT_TRUE(ReadPoseGraph(toro, SkipUnknownTags(), &graph, &report, &error))
      << error;
  EXPECT_EQ(graph.NumNodes(), 2u);
  EXPECT_EQ(graph.NumFactors(), 1u);
  // g2o content in a .graph file.
  Graph graph2;
  const std::string g2o =
      WriteText(dir + "/g2o_inside.graph", std::string(kV2) +
                                               "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 "
                                               "1\n");
  ASSERT_TRUE(ReadPoseGraph(g2o, {}, &graph2, &report, &error)) << error;
  EXPECT_EQ(graph2.NumFactors(), 1u);
  // Nothing recognised: the extension decides. PARAMS_SE3OFFSET is known to
  // the g2o reader only (which then finds nothing to read); the TORO reader
  // fails on the unknown tag.
  const std::string params = "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n";
  for (const char* name : {"params.graph", "params.g2o", "params.txt"}) {
    SCOPED_TRACE(name);
    Graph graph3;
    EXPECT_FALSE(ReadPoseGraph(WriteText(dir + "/" + name, params), {}, &graph3,
                               &report, &error));
    const bool toro = std::string(name) == "params.graph";
    EXPECT_TRUE(Contains(
        error, toro ? ":1: unknown tag 'PARAMS_SE3OFFSET'" : ": no records"))
        << error;
  }
  // An EDGE2 line after an unknown first tag in a .txt file is TORO.
  const std::string txt =
      WriteText(dir + "/late.txt",
                "VERTEX_LINE 5 1 1\nVERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n"
                "EDGE2 0 1 1 0 0 1 0 2 3 0 0\n");
  Graph graph4;
  ASSERT_TRUE(ReadPoseGraph(txt, SkipUnknownTags(), &graph4, &report, &error))
      << error;
  ASSERT_EQ(graph4.NumFactors(), 1u);
  // I22 = 2, I33 = 3 in TORO order (g2o order would read I13 = 2, I22 = 3).
  EXPECT_EQ(graph4.factors().begin()->second.information(1, 1), 2.0);
  EXPECT_EQ(graph4.factors().begin()->second.information(2, 2), 3.0);
}

TEST(G2oIoTest, WritePoseGraphPicksTheWriterByExtension) {
  const std::string dir = TempDir();
  Graph graph;
  std::string error;
  ASSERT_TRUE(Read(FixturePath("g2o_no_vertices.g2o"), &graph, nullptr, &error))
      << error;
  ASSERT_TRUE(WritePoseGraph(dir + "/out.graph", graph, &error)) << error;
  ASSERT_TRUE(WritePoseGraph(dir + "/out.G2O", graph, &error)) << error;
  ASSERT_TRUE(WritePoseGraph(dir + "/out.txt", graph, &error)) << error;
  EXPECT_EQ(ReadText(dir + "/out.graph").rfind("VERTEX2 10 ", 0), 0u);
  EXPECT_EQ(ReadText(dir + "/out.G2O").rfind("VERTEX_SE2 10 ", 0), 0u);
  EXPECT_EQ(ReadText(dir + "/out.txt").rfind("VERTEX_SE2 10 ", 0), 0u);
  for (const char* name : {"out.graph", "out.G2O", "out.txt"}) {
    Graph back;
    ASSERT_TRUE(ReadPoseGraph(dir + "/" + name, {}, &back, nullptr, &error))
        << error;
    ExpectSameGraph(graph, back);
  }
}

// ---------------------------------------------------------------------------
// Real data.

struct DatasetCase {
  const char* file;
  size_t nodes;
  size_t edges;
  bool has_vertices;
};

const std::vector<DatasetCase>& Datasets() {
  static const std::vector<DatasetCase> cases = {
      {"posegraph_2d/CSAIL.g2o", 1045, 1172, false},
      {"posegraph_2d/MIT.g2o", 808, 827, true},
      {"posegraph_2d/city10000.g2o", 10000, 20687, true},
      {"posegraph_2d/dpgo_input_M3500_g2o.g2o", 3500, 5453, true},
      {"posegraph_2d/gtsam_noisyToyGraph.txt", 4, 5, true},
      {"posegraph_2d/gtsam_pose2example.txt", 11, 12, true},
      {"posegraph_2d/intel.g2o", 1728, 2512, true},
      {"posegraph_2d/kitti_00.g2o", 4541, 4677, false},
      {"posegraph_2d/manhattan.g2o", 3500, 5453, false},
      {"posegraph_2d/vertigo_ring.g2o", 434, 459, true},
      {"posegraph_2d/groundtruth/vertigo_ring_groundTruth.g2o", 434, 459, true},
      {"posegraph_3d/gtsam_Klaus3.g2o", 3, 3, true},
      {"posegraph_3d/gtsam_pose3example-offdiagonal.txt", 2, 1, true},
      {"posegraph_3d/gtsam_pose3example.txt", 5, 6, true},
      {"posegraph_3d/gtsam_toyExample.g2o", 5, 6, true},
      {"posegraph_3d/parking-garage.g2o", 1661, 6275, true},
      {"posegraph_3d/smallGrid3D.g2o", 125, 297, true},
      {"posegraph_3d/sphere2500.g2o", 2500, 4949, true},
      {"posegraph_3d/tinyGrid3D.g2o", 9, 11, true},
      {"posegraph_3d/torus3D.g2o", 5000, 9048, true},
  };
  return cases;
}

TEST(G2oIoTest, AllSharedPoseGraphsLoadWithTheirCounts) {
  SLAM_REQUIRE_DATASET(DatasetPath("posegraph_2d/intel.g2o"));
  for (const DatasetCase& c : Datasets()) {
    SCOPED_TRACE(c.file);
    const std::string path = DatasetPath(c.file);
    Graph graph;
    GraphReadReport report;
    std::string error;
    ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, &report, &error)) << error;
    EXPECT_EQ(graph.NumNodes(), c.nodes);
    EXPECT_EQ(graph.NumFactors(), c.edges);
    EXPECT_EQ(report.edges, static_cast<int>(c.edges));
    EXPECT_EQ(report.vertices, c.has_vertices ? static_cast<int>(c.nodes) : 0);
    EXPECT_EQ(report.initialized_from_edges, !c.has_vertices);
    EXPECT_EQ(report.fixed, 0);
    EXPECT_EQ(report.repaired_information, 0);
    EXPECT_TRUE(report.warnings.empty());
    const bool is3 = std::string(c.file).find("3d") != std::string::npos;
    for (const auto& [key, node] : graph.nodes()) {
      ASSERT_EQ(key.kind, is3 ? NodeKind::kPose3 : NodeKind::kPose2);
      if (is3) {
        const Eigen::Map<const Eigen::Vector4d> q(node->value.data() + 3);
        EXPECT_NEAR(q.squaredNorm(), 1.0, 2e-15);
      } else {
        EXPECT_GE(node->value[2], -M_PI);
        EXPECT_LT(node->value[2], M_PI);
      }
    }
    EXPECT_TRUE(std::isfinite(graph.Chi2()));
  }
}

TEST(G2oIoTest, AllSharedPoseGraphsRoundTripExactly) {
  SLAM_REQUIRE_DATASET(DatasetPath("posegraph_2d/intel.g2o"));
  const std::string dir = TempDir();
  for (const DatasetCase& c : Datasets()) {
    SCOPED_TRACE(c.file);
    Graph graph;
    std::string error;
    ASSERT_TRUE(ReadPoseGraph(DatasetPath(c.file), {}, &graph, nullptr, &error))
        << error;
    ExpectRoundTrip(graph, dir, "round_trip.g2o");
  }
}

// CSAIL has no VERTEX lines: node 0 anchors the spanning tree at the
// identity, and every other node is its tree parent composed with the edge
// that reached it.
TEST(G2oIoTest, CsailInitialGuessComposesTheEdges) {
  const std::string path = DatasetPath("posegraph_2d/CSAIL.g2o");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadG2o(path, {}, &graph, &report, &error)) << error;
  EXPECT_TRUE(report.initialized_from_edges);
  ASSERT_EQ(graph.NumNodes(), 1045u);
  for (int id = 0; id < 1045; ++id) ASSERT_TRUE(graph.HasNode(Pose2Key(id)));
  EXPECT_EQ(Value(graph, Pose2Key(0)), (std::vector<double>{0, 0, 0}));
  // The first edge of the file is 0 -> 1 (0.082760 0.003050 0.284020).
  const std::vector<double>& x1 = Value(graph, Pose2Key(1));
  EXPECT_NEAR(x1[0], 0.082760, 1e-15);
  EXPECT_NEAR(x1[1], 0.003050, 1e-15);
  EXPECT_NEAR(x1[2], 0.284020, 1e-15);
  // Every node but the anchor is reproduced exactly by one of its edges; the
  // consecutive (odometry) edges explain most of them.
  std::map<int64_t, bool> explained;
  int by_odometry = 0;
  for (const auto& [id, f] : graph.factors()) {
    const Pose2 xi = NodePose2(*graph.FindNode(f.keys[0]));
    const Pose2 xj = NodePose2(*graph.FindNode(f.keys[1]));
    const Pose2 z = MeasurementPose2(f);
    const Pose2 fwd = xi * z, bwd = xj * z.Inverse();
    auto close = [](const Pose2& a, const Pose2& b) {
      return (a.t - b.t).norm() < 1e-9 &&
             std::abs(NormalizeAngle(a.theta - b.theta)) < 1e-9;
    };
    const bool odometry = f.keys[1].id == f.keys[0].id + 1;
    if (close(fwd, xj)) {
      if (!explained[f.keys[1].id] && odometry) ++by_odometry;
      explained[f.keys[1].id] = true;
    }
    if (close(bwd, xi)) explained[f.keys[0].id] = true;
  }
  for (int id = 1; id < 1045; ++id) EXPECT_TRUE(explained[id]) << id;
  EXPECT_GT(by_odometry, 900);
  // Loop closures are not all consistent with the tree.
  EXPECT_GT(graph.Chi2(), 1.0);
}

// g2o's chi2 of an EDGE_SE2 computed from the file's numbers alone:
// e = t2v(Z^-1 X_i^-1 X_j), chi2 = e^T Omega e.
double HandChi2Se2(const double* xi, const double* xj, const double* z,
                   const double* upper) {
  const double c = std::cos(xi[2]), s = std::sin(xi[2]);
  const double dx = xj[0] - xi[0], dy = xj[1] - xi[1];
  const double tx = c * dx + s * dy, ty = -s * dx + c * dy;
  const double cz = std::cos(z[2]), sz = std::sin(z[2]);
  double e[3];
  e[0] = cz * (tx - z[0]) + sz * (ty - z[1]);
  e[1] = -sz * (tx - z[0]) + cz * (ty - z[1]);
  const double dth = xj[2] - xi[2] - z[2];
  e[2] = std::atan2(std::sin(dth), std::cos(dth));
  const double o[3][3] = {{upper[0], upper[1], upper[2]},
                          {upper[1], upper[3], upper[4]},
                          {upper[2], upper[4], upper[5]}};
  double chi2 = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) chi2 += e[r] * o[r][k] * e[k];
  }
  return chi2;
}

// Parses "TAG numbers..." lines of a file with iostreams, independently of
// the reader under test.
std::vector<std::vector<double>> LinesWithTag(const std::string& path,
                                              const std::string& tag) {
  std::ifstream in(path);
  std::vector<std::vector<double>> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string t;
    ls >> t;
    if (t != tag) continue;
    std::vector<double> values;
    double v;
    while (ls >> v) values.push_back(v);
    out.push_back(values);
  }
  return out;
}

TEST(G2oIoTest, Chi2MatchesAHandComputationOfTheG2oError2d) {
  for (const char* file :
       {"posegraph_2d/gtsam_noisyToyGraph.txt", "posegraph_2d/intel.g2o"}) {
    SCOPED_TRACE(file);
    const std::string path = DatasetPath(file);
    SLAM_REQUIRE_DATASET(path);
    Graph graph;
    std::string error;
    ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, nullptr, &error)) << error;
    std::map<int, std::vector<double>> vertices;
    for (const auto& v : LinesWithTag(path, "VERTEX_SE2")) {
      vertices[static_cast<int>(v[0])] = {v[1], v[2], v[3]};
    }
    const auto edges = LinesWithTag(path, "EDGE_SE2");
    ASSERT_EQ(edges.size(), graph.NumFactors());
    double total = 0.0;
    size_t k = 0;
    for (const auto& [id, factor] : graph.factors()) {
      const std::vector<double>& e = edges[k++];
      const double hand =
          HandChi2Se2(vertices[static_cast<int>(e[0])].data(),
                      vertices[static_cast<int>(e[1])].data(), &e[2], &e[5]);
      double chi2 = 0.0;
      ASSERT_TRUE(graph.FactorChi2(factor, &chi2));
      EXPECT_NEAR(chi2, hand, 1e-9 * std::max(1.0, hand)) << "edge " << k;
      total += hand;
    }
    EXPECT_NEAR(graph.Chi2(), total, 1e-9 * std::max(1.0, total));
    EXPECT_GT(total, 0.0);
  }
}

// Same in 3D with a full off-diagonal information matrix: E = Z^-1 Xi^-1 Xj,
// e = (t_E, qvec(E)) with w >= 0.
TEST(G2oIoTest, Chi2MatchesAHandComputationOfTheG2oError3d) {
  for (const char* file : {"posegraph_3d/gtsam_pose3example-offdiagonal.txt",
                           "posegraph_3d/smallGrid3D.g2o"}) {
    SCOPED_TRACE(file);
    const std::string path = DatasetPath(file);
    SLAM_REQUIRE_DATASET(path);
    Graph graph;
    std::string error;
    ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, nullptr, &error)) << error;
    auto isometry = [](const double* v) {
      Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
      x.linear() =
          Eigen::Quaterniond(v[6], v[3], v[4], v[5]).normalized().matrix();
      x.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      return x;
    };
    // The files' vertices agree with some edges exactly: move every vertex
    // a little (in the graph and in the hand computation) so that each edge
    // has an error.
    std::map<int, Eigen::Isometry3d> vertices;
    for (const auto& line : LinesWithTag(path, "VERTEX_SE3:QUAT")) {
      const int id = static_cast<int>(line[0]);
      std::vector<double> v(line.begin() + 1, line.end());
      v[0] += 0.01 * (id % 3);
      v[1] -= 0.02;
      v[3] += 0.01 * (id % 2);
      v[5] -= 0.015;
      const Eigen::Quaterniond q =
          Eigen::Quaterniond(v[6], v[3], v[4], v[5]).normalized();
      v[3] = q.x();
      v[4] = q.y();
      v[5] = q.z();
      v[6] = q.w();
      ASSERT_TRUE(graph.HasNode(Pose3Key(id)));
      graph.FindNode(Pose3Key(id))->value = v;
      vertices[id] = isometry(v.data());
    }
    const auto edges = LinesWithTag(path, "EDGE_SE3:QUAT");
    ASSERT_EQ(edges.size(), graph.NumFactors());
    size_t k = 0;
    double total = 0.0;
    for (const auto& [id, factor] : graph.factors()) {
      const std::vector<double>& e = edges[k++];
      const Eigen::Isometry3d err = isometry(&e[2]).inverse() *
                                    vertices[static_cast<int>(e[0])].inverse() *
                                    vertices[static_cast<int>(e[1])];
      Eigen::Quaterniond q(err.linear());
      if (q.w() < 0) q.coeffs() = -q.coeffs();
      Eigen::Matrix<double, 6, 1> r;
      r << err.translation(), q.vec();
      Eigen::Matrix<double, 6, 6> omega;
      int n = 9;
      for (int a = 0; a < 6; ++a) {
        for (int b = a; b < 6; ++b) omega(a, b) = omega(b, a) = e[n++];
      }
      const double hand = r.dot(omega * r);
      double chi2 = 0.0;
      ASSERT_TRUE(graph.FactorChi2(factor, &chi2));
      EXPECT_GT(hand, 1e-3) << "edge " << k;
      EXPECT_NEAR(chi2, hand, 1e-9 * hand) << "edge " << k;
      total += hand;
    }
    EXPECT_GT(total, 0.0);
    EXPECT_NEAR(graph.Chi2(), total, 1e-9 * total);
  }
}

double SecondsToLoad(const std::string& path, size_t* nodes) {
  double best = 1e9;
  for (int run = 0; run < 3; ++run) {
    Graph graph;
    std::string error;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = ReadG2o(path, {}, &graph, nullptr, &error);
    const auto stop = std::chrono::steady_clock::now();
    EXPECT_TRUE(ok) << error;
    *nodes = graph.NumNodes();
    best = std::min(best, std::chrono::duration<double>(stop - start).count());
  }
  return best;
}

// Load times are printed for the record; speed itself is a benchmark matter
// (scripts/benchmark_posegraph.py), not a pass/fail unit test.
TEST(G2oIoTest, LargeFilesLoad) {
  const std::string torus = DatasetPath("posegraph_3d/torus3D.g2o");
  const std::string city = DatasetPath("posegraph_2d/city10000.g2o");
  SLAM_REQUIRE_DATASET(torus);
  SLAM_REQUIRE_DATASET(city);
  size_t nodes = 0;
  const double torus_seconds = SecondsToLoad(torus, &nodes);
  EXPECT_EQ(nodes, 5000u);
  const double city_seconds = SecondsToLoad(city, &nodes);
  EXPECT_EQ(nodes, 10000u);
  std::printf(
      "load times (best of 3): torus3D.g2o %.4f s, city10000.g2o "
      "%.4f s\n",
      torus_seconds, city_seconds);
}

}  // namespace
}  // namespace slam
