// Tests of the TORO / HOG-Man reader and writer (datasets/toro_io.h).
#include "datasets/toro_io.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"
#include "datasets/g2o_io.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::DatasetPath;
using ::slam::testing::FixturePath;
using ::slam::testing::ReadText;
using ::slam::testing::TempDir;

std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path;
}

// The fixture has an EQUIV line, a tag this reader does not read.
GraphReadOptions SkipUnknownTags() {
  GraphReadOptions options;
  options.skip_unknown_tags = true;
  return options;
}

uint64_t Bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof(b));
  return b;
}

// Bit-exact comparison, except SE(3) rotations (Euler angles in the file),
// compared as rotations to `rotation_tolerance` radians.
void ExpectSameGraph(const Graph& a, const Graph& b,
                     double rotation_tolerance = 0.0) {
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  ASSERT_EQ(a.NumFactors(), b.NumFactors());
  auto same_values = [&](const double* x, const double* y, int n, bool is3,
                         const std::string& what) {
    const int exact = is3 ? 3 : n;
    for (int k = 0; k < exact; ++k) {
      EXPECT_EQ(Bits(x[k]), Bits(y[k]))
          << what << " " << k << ": " << x[k] << " vs " << y[k];
    }
    if (is3) {
      const Eigen::Quaterniond qx(x[6], x[3], x[4], x[5]);
      const Eigen::Quaterniond qy(y[6], y[3], y[4], y[5]);
      EXPECT_LE(qx.angularDistance(qy), rotation_tolerance) << what;
      EXPECT_NEAR(qy.squaredNorm(), 1.0, 2e-15) << what;
    }
  };
  auto na = a.nodes().begin();
  auto nb = b.nodes().begin();
  for (; na != a.nodes().end(); ++na, ++nb) {
    ASSERT_EQ(na->first, nb->first);
    EXPECT_EQ(na->second->fixed, nb->second->fixed);
    ASSERT_EQ(na->second->value.size(), nb->second->value.size());
    same_values(na->second->value.data(), nb->second->value.data(),
                static_cast<int>(na->second->value.size()),
                na->first.kind == NodeKind::kPose3, na->first.ToString());
  }
  auto fa = a.factors().begin();
  auto fb = b.factors().begin();
  for (; fa != a.factors().end(); ++fa, ++fb) {
    const Factor& x = fa->second;
    const Factor& y = fb->second;
    ASSERT_EQ(x.type, y.type);
    ASSERT_EQ(x.keys, y.keys);
    ASSERT_EQ(x.measurement.size(), y.measurement.size());
    same_values(x.measurement.data(), y.measurement.data(),
                static_cast<int>(x.measurement.size()),
                x.type == FactorType::kBetweenSE3,
                "factor " + std::to_string(fa->first));
    ASSERT_EQ(x.information.rows(), y.information.rows());
    for (int r = 0; r < x.information.rows(); ++r) {
      for (int c = 0; c < x.information.cols(); ++c) {
        EXPECT_EQ(Bits(x.information(r, c)), Bits(y.information(r, c)))
            << "factor " << fa->first << " information " << r << "," << c;
      }
    }
  }
}

std::vector<const Factor*> Factors(const Graph& graph) {
  std::vector<const Factor*> out;
  for (const auto& [id, f] : graph.factors()) out.push_back(&f);
  return out;
}

// HOG-Man's RotationMatrix3(roll, pitch, yaw), written out.
Eigen::Matrix3d HogmanRotation(double roll, double pitch, double yaw) {
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  const double sy = std::sin(yaw), cy = std::cos(yaw);
  Eigen::Matrix3d r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

// HOG-Man's RotationMatrix3::angles().
Eigen::Vector3d HogmanAngles(const Eigen::Matrix3d& m) {
  return Eigen::Vector3d(std::atan2(m(2, 1), m(2, 2)),
                         std::atan2(-m(2, 0), std::hypot(m(2, 1), m(2, 2))),
                         std::atan2(m(1, 0), m(0, 0)));
}

// ---------------------------------------------------------------------------
// Shared data files.

TEST(ToroIoTest, ReadsW100WithEquivLinesSkipped) {
  const std::string path = DatasetPath("posegraph_toro/gtsam_w100.graph");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadToro(path, {}, &graph, &report, &error)) << error;
  EXPECT_EQ(graph.NumNodes(), 100u);
  EXPECT_EQ(graph.NumFactors(), 300u);
  EXPECT_EQ(report.vertices, 100);
  EXPECT_EQ(report.edges, 300);
  EXPECT_FALSE(report.initialized_from_edges);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0], "unknown tag 'EQUIV' (40 lines) skipped");
  // "EDGE2 1 0 -0.99879 0.0417574 -0.00818381 1 0 1 1 0 0".
  const Factor& first = graph.factors().begin()->second;
  EXPECT_EQ(first.type, FactorType::kBetweenSE2);
  EXPECT_EQ(first.keys, (std::vector<Key>{Pose2Key(1), Pose2Key(0)}));
  EXPECT_EQ(first.measurement,
            Eigen::Vector3d(-0.99879, 0.0417574, -0.00818381));
  EXPECT_EQ(first.information, Eigen::MatrixXd::Identity(3, 3));
  // "VERTEX2 1 0.995595 0.0837204 0.0146728".
  EXPECT_EQ(graph.FindNode(Pose2Key(1))->value,
            (std::vector<double>{0.995595, 0.0837204, 0.0146728}));
  // The dispatcher picks the TORO reader.
  Graph dispatched;
  ASSERT_TRUE(ReadPoseGraph(path, {}, &dispatched, nullptr, &error)) << error;
  ExpectSameGraph(graph, dispatched);
}

TEST(ToroIoTest, ReadsExampleGraphWithBearingRangeLines) {
  const std::string path = DatasetPath("posegraph_toro/gtsam_example.graph");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, &report, &error)) << error;
  // 95 poses, 94 odometry edges, 422 BR lines to landmarks (read as
  // range-bearing factors, datasets/toro_io.h).
  EXPECT_EQ(report.vertices, 95);
  EXPECT_EQ(report.edges, 94 + 422);
  EXPECT_TRUE(report.warnings.empty());
  int poses = 0, between = 0, bearing_range = 0;
  for (const auto& [key, node] : graph.nodes()) {
    poses += key.kind == NodeKind::kPose2;
  }
  for (const auto& [id, f] : graph.factors()) {
    if (f.type == FactorType::kBetweenSE2) {
      ++between;
      EXPECT_EQ(f.keys[1].id, f.keys[0].id + 1);
    }
    bearing_range += f.type == FactorType::kRangeBearing2;
  }
  EXPECT_EQ(poses, 95);
  EXPECT_EQ(between, 94);
  EXPECT_EQ(bearing_range, 422);
  EXPECT_EQ(report.landmarks_initialized,
            static_cast<int>(graph.NumNodes()) - 95);
}

TEST(ToroIoTest, SharedFilesRoundTripExactly) {
  const std::string dir = TempDir();
  for (const char* file : {"posegraph_toro/gtsam_w100.graph",
                           "posegraph_toro/gtsam_example.graph"}) {
    SCOPED_TRACE(file);
    const std::string path = DatasetPath(file);
    SLAM_REQUIRE_DATASET(path);
    Graph graph;
    std::string error;
    ASSERT_TRUE(ReadToro(path, {}, &graph, nullptr, &error)) << error;
    ASSERT_TRUE(WriteToro(dir + "/out.graph", graph, &error)) << error;
    Graph back;
    ASSERT_TRUE(ReadToro(dir + "/out.graph", {}, &back, nullptr, &error))
        << error;
    ExpectSameGraph(graph, back);
  }
}

// ---------------------------------------------------------------------------
// 2D.

TEST(ToroIoTest, Edge2InformationOrderIsI11I12I22I33I13I23) {
  const std::string path = FixturePath("toro_2d.graph");
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadToro(path, SkipUnknownTags(), &graph, &report, &error))
      << error;
  ASSERT_EQ(graph.NumFactors(), 3u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0], "unknown tag 'EQUIV' (1 line) skipped");
  const std::vector<const Factor*> f = Factors(graph);
  Eigen::Matrix3d expected;
  // "10 1 20 30 2 3".
  expected << 10, 1, 2, 1, 20, 3, 2, 3, 30;
  EXPECT_EQ(f[0]->information, Eigen::MatrixXd(expected));
  EXPECT_EQ(f[1]->information, Eigen::MatrixXd(expected));
  EXPECT_EQ(f[0]->keys, f[1]->keys);  // Repeated edge kept.
  // "EDGE2 2 1 -1.0 -0.2 0.35 11 -1 21 31 -2 -3".
  expected << 11, -1, -2, -1, 21, -3, -2, -3, 31;
  EXPECT_EQ(f[2]->information, Eigen::MatrixXd(expected));
  EXPECT_EQ(f[2]->keys, (std::vector<Key>{Pose2Key(2), Pose2Key(1)}));
  EXPECT_EQ(f[2]->measurement, Eigen::Vector3d(-1.0, -0.2, 0.35));
}

TEST(ToroIoTest, RoundTrip2dWithFixedNodesIsExact) {
  const std::string dir = TempDir();
  Graph graph;
  std::string error;
  ASSERT_TRUE(ReadToro(FixturePath("toro_2d.graph"), SkipUnknownTags(), &graph,
                       nullptr, &error))
      << error;
  graph.SetFixed(Pose2Key(1), true);
  // A value that needs 17 digits.
  graph.FindNode(Pose2Key(2))->value[0] = 0.1 + 0.2;
  ASSERT_TRUE(WritePoseGraph(dir + "/out.graph", graph, &error)) << error;
  const std::string text = ReadText(dir + "/out.graph");
  EXPECT_EQ(text.rfind("VERTEX2 0 0 0 0\n", 0), 0u) << text;
  EXPECT_NE(text.find("\nFIX 1\n"), std::string::npos) << text;
  // Shortest round-trip digits: 0.05 reads back as the same double, and
  // 0.1 + 0.2 needs all 17.
  EXPECT_NE(text.find("VERTEX2 2 0.30000000000000004 "), std::string::npos)
      << text;
  EXPECT_NE(text.find("EDGE2 0 1 1 0.05 0.04 10 1 20 30 2 3\n"),
            std::string::npos)
      << text;
  Graph back;
  GraphReadReport report;
  ASSERT_TRUE(ReadPoseGraph(dir + "/out.graph", {}, &back, &report, &error))
      << error;
  EXPECT_EQ(report.fixed, 1);
  ExpectSameGraph(graph, back);
}

// ---------------------------------------------------------------------------
// 3D.

TEST(ToroIoTest, Vertex3UsesRzRyRxEulerAngles) {
  Graph graph;
  std::string error;
  ASSERT_TRUE(
      ReadToro(FixturePath("toro_3d.graph"), {}, &graph, nullptr, &error))
      << error;
  ASSERT_EQ(graph.NumNodes(), 3u);
  const Pose3 x1 = NodePose3(*graph.FindNode(Pose3Key(1)));
  EXPECT_EQ(x1.t, Eigen::Vector3d(1.001, 0.2, -0.1));
  EXPECT_LT((x1.q.toRotationMatrix() - HogmanRotation(0.101, -0.2, 0.3005))
                .cwiseAbs()
                .maxCoeff(),
            1e-15);
  // A pure yaw is a rotation about z.
  ASSERT_TRUE(ReadToroFromText("yaw", "VERTEX3 7 0 0 0 0 0 0.5\n", {}, &graph,
                               nullptr, &error) == false);  // Not empty.
  Graph yaw;
  ASSERT_TRUE(ReadToroFromText("yaw", "VERTEX3 7 0 0 0 0 0 0.5\n", {}, &yaw,
                               nullptr, &error))
      << error;
  const std::vector<double>& v = yaw.FindNode(Pose3Key(7))->value;
  EXPECT_NEAR(v[3], 0.0, 1e-17);
  EXPECT_NEAR(v[4], 0.0, 1e-17);
  EXPECT_NEAR(v[5], std::sin(0.25), 1e-16);
  EXPECT_NEAR(v[6], std::cos(0.25), 1e-16);
}

// Omega = D Omega_h D with D = diag(1, 1, 1, 2, 2, 2), exactly.
TEST(ToroIoTest, Edge3InformationIsConvertedToQuaternionVectorUnits) {
  Graph graph;
  std::string error;
  ASSERT_TRUE(
      ReadToro(FixturePath("toro_3d.graph"), {}, &graph, nullptr, &error))
      << error;
  const std::vector<const Factor*> f = Factors(graph);
  ASSERT_EQ(f.size(), 2u);
  Eigen::Matrix<double, 6, 6> hogman;
  hogman << 100, 1, 2, 3, 4, 5,  //
      1, 200, 6, 7, 8, 9,        //
      2, 6, 300, 10, 11, 12,     //
      3, 7, 10, 400, 13, 14,     //
      4, 8, 11, 13, 500, 15,     //
      5, 9, 12, 14, 15, 600;
  Eigen::Matrix<double, 6, 6> expected;
  expected << 100, 1, 2, 6, 8, 10,  //
      1, 200, 6, 14, 16, 18,        //
      2, 6, 300, 20, 22, 24,        //
      6, 14, 20, 1600, 52, 56,      //
      8, 16, 22, 52, 2000, 60,      //
      10, 18, 24, 56, 60, 2400;
  const Eigen::Matrix<double, 6, 1> d =
      (Eigen::Matrix<double, 6, 1>() << 1, 1, 1, 2, 2, 2).finished();
  EXPECT_EQ(Eigen::MatrixXd(d.asDiagonal() * hogman * d.asDiagonal()),
            Eigen::MatrixXd(expected));
  EXPECT_EQ(f[0]->information, Eigen::MatrixXd(expected));
  EXPECT_EQ(f[1]->information, Eigen::MatrixXd(expected));
}

// For small errors our chi2 (quaternion-vector error, converted information)
// equals HOG-Man's chi2 (Euler-angle error, file information) to first order.
TEST(ToroIoTest, Edge3Chi2MatchesHogmanChi2ForSmallErrors) {
  const std::string path = FixturePath("toro_3d.graph");
  Graph graph;
  std::string error;
  ASSERT_TRUE(ReadToro(path, {}, &graph, nullptr, &error)) << error;
  // Values from the file, as HOG-Man sees them.
  const double v[3][6] = {{0, 0, 0, 0, 0, 0},
                          {1.001, 0.2, -0.1, 0.101, -0.2, 0.3005},
                          {2.0, 0.5, 0.3, 0.2, 0.1, -0.4}};
  const double z[2][6] = {{1.0, 0.2, -0.1, 0.1, -0.2, 0.3},
                          {1.100709292, 0.009535239, 0.184788297, -0.007538875,
                           0.184070889, -0.741437442}};
  auto isometry = [](const double* p) {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    x.linear() = HogmanRotation(p[3], p[4], p[5]);
    x.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return x;
  };
  Eigen::Matrix<double, 6, 6> omega_h;
  omega_h << 100, 1, 2, 3, 4, 5, 1, 200, 6, 7, 8, 9, 2, 6, 300, 10, 11, 12, 3,
      7, 10, 400, 13, 14, 4, 8, 11, 13, 500, 15, 5, 9, 12, 14, 15, 600;
  const std::vector<const Factor*> f = Factors(graph);
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    const Eigen::Isometry3d e = isometry(z[k]).inverse() *
                                isometry(v[k]).inverse() * isometry(v[k + 1]);
    Eigen::Matrix<double, 6, 1> e_h;
    e_h << e.translation(), HogmanAngles(e.linear());
    const double chi2_hogman = e_h.dot(omega_h * e_h);
    double chi2 = 0.0;
    ASSERT_TRUE(graph.FactorChi2(*f[k], &chi2));
    EXPECT_GT(chi2_hogman, 1e-4);
    // Errors are ~1e-3: second-order differences ~1e-3 relative.
    EXPECT_NEAR(chi2, chi2_hogman, 1e-2 * chi2_hogman);
    // Without the conversion the rotation part would be 4 times too small.
    Eigen::Matrix<double, 6, 1> e_ours;
    e_ours << e_h.head<3>(), 0.5 * e_h.tail<3>();
    EXPECT_GT(std::abs(e_ours.dot(omega_h * e_ours) - chi2_hogman),
              0.1 * chi2_hogman);
  }
}

TEST(ToroIoTest, RoundTrip3d) {
  const std::string dir = TempDir();
  Graph graph;
  std::string error;
  ASSERT_TRUE(
      ReadToro(FixturePath("toro_3d.graph"), {}, &graph, nullptr, &error))
      << error;
  graph.SetFixed(Pose3Key(0), true);
  ASSERT_TRUE(WriteToro(dir + "/out.graph", graph, &error)) << error;
  const std::string text = ReadText(dir + "/out.graph");
  EXPECT_EQ(text.rfind("VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 1.001 ", 0), 0u)
      << text;
  // The information goes back to the file's units.
  EXPECT_NE(text.find(" 100 1 2 3 4 5 200 6 7 8 9 300 10 11 12 400 13 14 500 "
                      "15 600\n"),
            std::string::npos)
      << text;
  Graph back;
  ASSERT_TRUE(ReadToro(dir + "/out.graph", {}, &back, nullptr, &error))
      << error;
  ExpectSameGraph(graph, back, 1e-14);
  // A 3D g2o graph (quaternions) through TORO and back.
  const std::string garage = DatasetPath("posegraph_3d/sphere2500.g2o");
  SLAM_REQUIRE_DATASET(garage);
  Graph g2o;
  ASSERT_TRUE(ReadG2o(garage, {}, &g2o, nullptr, &error)) << error;
  ASSERT_TRUE(WriteToro(dir + "/sphere.graph", g2o, &error)) << error;
  Graph toro;
  ASSERT_TRUE(ReadPoseGraph(dir + "/sphere.graph", {}, &toro, nullptr, &error))
      << error;
  ExpectSameGraph(g2o, toro, 1e-14);
  EXPECT_NEAR(toro.Chi2(), g2o.Chi2(), 1e-9 * g2o.Chi2());
}

// ---------------------------------------------------------------------------
// Errors.

TEST(ToroIoTest, MalformedInputFailsWithFileLineAndProblem) {
  const std::string dir = TempDir();
  const std::string v2 = "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n";
  const std::string info21 = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";
  const struct {
    const char* name;
    std::string text;
    int line;
    const char* problem;
  } cases[] = {
      {"missing", v2 + "EDGE2 0 1 1 0 0 1 0 1 1 0\n", 3, "(missing fields)"},
      {"extra", v2 + "EDGE2 0 1 1 0 0 1 0 1 1 0 0 0\n", 3, "(extra fields)"},
      {"bad_number", v2 + "EDGE2 0 1 1 0 0 1 0 1 1 0 1..\n", 3,
       "bad number '1..'"},
      {"nan", "VERTEX2 0 nan 0 0\n", 1, "non-finite number 'nan'"},
      {"unknown_vertex", v2 + "EDGE2 0 17 1 0 0 1 0 1 1 0 0\n", 3,
       "unknown vertex id 17"},
      {"self_edge", v2 + "EDGE2 1 1 1 0 0 1 0 1 1 0 0\n", 3, "self-edge"},
      {"duplicate", v2 + "VERTEX2 0 0 0 0\n", 3, "duplicate vertex id 0"},
      {"mixed", v2 + "VERTEX3 2 0 0 0 0 0 0\n", 3,
       "the file mixes SE(2) and SE(3) records"},
      // I22 = -1 in TORO order (it would be I13 in g2o order).
      {"not_pd", v2 + "EDGE2 0 1 1 0 0 1 0 -1 1 0 0\n", 3,
       "information matrix is not positive definite"},
      {"edge3_missing",
       "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 0 0 0 0 0 0\n"
       "EDGE3 0 1 1 0 0 0 0 0 1 0 0\n",
       3, "EDGE3 needs 29 fields after the tag, found 11 (missing fields)"},
      {"fix_unknown", v2 + "FIX 3\n", 3, "FIX of unknown vertex id 3"},
      {"edge3_not_pd",
       "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 0 0 0 0 0 0\n"
       "EDGE3 0 1 1 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 -1 0 0 "
       "0 1 0 0 1 0 1\n",
       3, "information matrix is not positive definite"},
  };
  (void)info21;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = WriteText(dir + "/" + c.name + ".graph", c.text);
    Graph graph;
    std::string error;
    EXPECT_FALSE(ReadToro(path, {}, &graph, nullptr, &error));
    const std::string prefix = path + ":" + std::to_string(c.line) + ": ";
    EXPECT_EQ(error.substr(0, prefix.size()), prefix) << error;
    EXPECT_NE(error.find(c.problem), std::string::npos) << error;
    EXPECT_EQ(graph.NumNodes(), 0u);
  }
  Graph graph;
  std::string error;
  EXPECT_FALSE(ReadToro(dir + "/none.graph", {}, &graph, nullptr, &error));
  EXPECT_EQ(error.rfind(dir + "/none.graph: cannot open", 0), 0u) << error;
}

TEST(ToroIoTest, EdgesWithoutVerticesAreInitialized) {
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadToroFromText("chain",
                               "EDGE2 0 1 1 0 0.5 1 0 1 1 0 0\n"
                               "EDGE2 1 2 1 0 0.5 1 0 1 1 0 0\n",
                               {}, &graph, &report, &error))
      << error;
  EXPECT_TRUE(report.initialized_from_edges);
  const std::vector<double>& x2 = graph.FindNode(Pose2Key(2))->value;
  const Pose2 expected = Pose2(1, 0, 0.5) * Pose2(1, 0, 0.5);
  EXPECT_NEAR(x2[0], expected.t.x(), 1e-15);
  EXPECT_NEAR(x2[1], expected.t.y(), 1e-15);
  EXPECT_NEAR(x2[2], 1.0, 1e-15);
}

TEST(ToroIoTest, WriterRejectsPriorsAndLeavesNoFile) {
  const std::string dir = TempDir();
  Graph graph;
  graph.AddNode(Pose2Key(0), {0, 0, 0});
  Factor prior;
  std::string error;
  ASSERT_TRUE(MakePriorSE2(Pose2Key(0), Pose2(1, 2, 0.5),
                           Eigen::Matrix3d::Identity(), &prior, &error));
  ASSERT_GE(graph.AddFactor(std::move(prior)), 0);
  EXPECT_FALSE(WriteToro(dir + "/prior.graph", graph, &error));
  EXPECT_NE(error.find("prior"), std::string::npos) << error;
  EXPECT_FALSE(WriteToro(dir + "/missing/x.graph", graph, &error));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  // The g2o writer takes it.
  EXPECT_TRUE(WritePoseGraph(dir + "/prior.g2o", graph, &error)) << error;
  Graph empty;
  EXPECT_FALSE(WriteToro(dir + "/no/such/dir.graph", empty, &error));
  EXPECT_EQ(error.rfind(dir + "/no/such/dir.graph: ", 0), 0u) << error;
}

}  // namespace
}  // namespace slam
