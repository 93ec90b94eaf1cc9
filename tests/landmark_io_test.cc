// Round trips and bad input for the landmark file formats: the g2o landmark
// tags and this project's camera tags (datasets/g2o_io.h), iSAM
// (datasets/isam_io.h), TORO BR lines (datasets/toro_io.h) and the stereo VO
// files (datasets/stereo_vo_io.h).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/graph.h"
#include "datasets/g2o_io.h"
#include "datasets/isam_io.h"
#include "datasets/stereo_vo_io.h"
#include "datasets/toro_io.h"
#include "factors/landmark_factors.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::Contains;
using ::slam::testing::Exists;
using ::slam::testing::ReadText;
using ::slam::testing::TempDir;
using ::slam::testing::WriteText;
using Rng = ::slam::testing::TestRng;

// Exactly symmetric (the files hold the upper triangle only).
Eigen::MatrixXd Sym(const Eigen::MatrixXd& m) {
  return 0.5 * (m + m.transpose());
}

void Add(Graph* graph, bool ok, const Factor& f, const std::string& error) {
  ASSERT_TRUE(ok) << error;
  ASSERT_GE(graph->AddFactor(f), 0);
}

// A 2D graph with every 2D factor kind, poses and points sharing one id
// space (points 100+).
void Build2d(Graph* graph) {
  Rng rng(11);
  std::string error;
  Factor f;
  for (int i = 0; i < 5; ++i) {
    graph->AddNode(Pose2Key(i), Pose2Value(rng.RandomPose2()));
  }
  for (int j = 100; j < 103; ++j) {
    graph->AddNode(Point2Key(j), {rng.Uniform(-9, 9), rng.Uniform(-9, 9)});
  }
  graph->SetFixed(Point2Key(101), true);
  for (int i = 0; i + 1 < 5; ++i) {
    Add(graph,
        MakeBetweenSE2(Pose2Key(i), Pose2Key(i + 1), rng.RandomPose2(1.0),
                       Sym(rng.ScaledInformation(3)), &f, &error),
        f, error);
    Add(graph,
        MakeRelativePoint2(Pose2Key(i), Point2Key(100 + i % 3),
                           Eigen::Vector2d(rng.Normal(), rng.Normal()),
                           Sym(rng.ScaledInformation(2)), &f, &error),
        f, error);
    Add(graph,
        MakeRangeBearing2(Pose2Key(i), Point2Key(100 + (i + 1) % 3),
                          rng.Uniform(1, 9), rng.Uniform(-3, 3),
                          Sym(rng.ScaledInformation(2)), &f, &error),
        f, error);
  }
}

// A 3D graph with every 3D factor kind, two sensor offsets, two pinhole and
// one stereo calibration.
void Build3d(Graph* graph) {
  Rng rng(12);
  std::string error;
  Factor f;
  for (int i = 0; i < 4; ++i) {
    graph->AddNode(Pose3Key(i), Pose3Value(rng.RandomPose3()));
  }
  for (int j = 10; j < 14; ++j) {
    const Eigen::Vector3d p = rng.Normal3() * 5.0;
    graph->AddNode(Point3Key(j), {p.x(), p.y(), p.z()});
  }
  StereoCalibration stereo{718.1, 718.2, 607.3, 185.4, 0.54};
  PinholeCalibration plain{458.6, 457.3, 367.2, 248.4, 0, 0, 0, 0};
  PinholeCalibration radtan{458.6,  457.3,  367.2,  248.4,
                            -0.283, 0.0739, 1.9e-4, 1.7e-5};
  Add(graph,
      MakePriorSE3(Pose3Key(0), rng.RandomPose3(),
                   Sym(rng.ScaledInformation(6)), &f, &error),
      f, error);
  for (int i = 0; i < 4; ++i) {
    if (i + 1 < 4) {
      Add(graph,
          MakeBetweenSE3(Pose3Key(i), Pose3Key(i + 1), rng.RandomPose3(1.0),
                         Sym(rng.ScaledInformation(6)), &f, &error),
          f, error);
    }
    const Key point = Point3Key(10 + i);
    Add(graph,
        MakeRelativePoint3(Pose3Key(i), point, rng.Normal3(),
                           i % 2 == 0 ? Pose3() : rng.RandomPose3(0.2),
                           Sym(rng.ScaledInformation(3)), &f, &error),
        f, error);
    Add(graph,
        MakeStereo(Pose3Key(i), point, stereo,
                   Eigen::Vector3d(rng.Uniform(0, 1200), rng.Uniform(0, 1200),
                                   rng.Uniform(0, 370)),
                   Sym(rng.ScaledInformation(3)), &f, &error),
        f, error);
    Add(graph,
        MakeReprojection(
            Pose3Key(i), point, i % 2 == 0 ? plain : radtan,
            Eigen::Vector2d(rng.Uniform(0, 752), rng.Uniform(0, 480)),
            Sym(rng.ScaledInformation(2)), &f, &error),
        f, error);
  }
}

// Nodes (values bit for bit, fixed flags) and factors (type, keys,
// measurement and information bit for bit) equal.
void ExpectSameGraph(const Graph& a, const Graph& b) {
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  ASSERT_EQ(a.NumFactors(), b.NumFactors());
  for (const auto& [key, node] : a.nodes()) {
    const Node* other = b.FindNode(key);
    ASSERT_NE(other, nullptr) << key.ToString();
    EXPECT_EQ(node->value, other->value) << key.ToString();
    EXPECT_EQ(node->fixed, other->fixed) << key.ToString();
  }
  auto ia = a.factors().begin();
  auto ib = b.factors().begin();
  for (; ia != a.factors().end(); ++ia, ++ib) {
    const Factor& fa = ia->second;
    const Factor& fb = ib->second;
    EXPECT_EQ(fa.type, fb.type);
    EXPECT_EQ(fa.keys, fb.keys);
    EXPECT_EQ(fa.measurement, fb.measurement) << FactorTypeName(fa.type);
    EXPECT_EQ(fa.information, fb.information) << FactorTypeName(fa.type);
  }
}

void ExpectG2oRoundTrip(const Graph& graph) {
  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(WriteG2o(dir + "/a.g2o", graph, &error)) << error;
  Graph back;
  GraphReadReport report;
  ASSERT_TRUE(ReadPoseGraph(dir + "/a.g2o", {}, &back, &report, &error))
      << error;
  EXPECT_TRUE(report.warnings.empty());
  ExpectSameGraph(graph, back);
  // And the file reproduces itself.
  ASSERT_TRUE(WriteG2o(dir + "/b.g2o", back, &error)) << error;
  EXPECT_EQ(ReadText(dir + "/a.g2o"), ReadText(dir + "/b.g2o"));
}

TEST(LandmarkIoTest, G2o2dRoundTripIsBitExact) {
  Graph graph;
  Build2d(&graph);
  ExpectG2oRoundTrip(graph);
  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(WriteG2o(dir + "/a.g2o", graph, &error));
  const std::string text = ReadText(dir + "/a.g2o");
  EXPECT_TRUE(Contains(text, "VERTEX_XY 100 "));
  EXPECT_TRUE(Contains(text, "EDGE_SE2_XY 0 100 "));
  EXPECT_TRUE(Contains(text, "EDGE_SE2_RANGE_BEARING 0 101 "));
  EXPECT_TRUE(Contains(text, "FIX 101"));
}

TEST(LandmarkIoTest, G2o3dRoundTripIsBitExact) {
  Graph graph;
  Build3d(&graph);
  ExpectG2oRoundTrip(graph);
  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(WriteG2o(dir + "/a.g2o", graph, &error));
  const std::string text = ReadText(dir + "/a.g2o");
  // Identity offset (0, shared with the prior), one more offset per
  // non-identity draw, one stereo and two pinhole records.
  EXPECT_TRUE(Contains(text, "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n"));
  EXPECT_TRUE(Contains(text, "PARAMS_STEREO "));
  EXPECT_TRUE(Contains(text, "PARAMS_PINHOLE "));
  EXPECT_TRUE(Contains(text, "VERTEX_TRACKXYZ 10 "));
  EXPECT_TRUE(Contains(text, "EDGE_SE3_TRACKXYZ 0 10 0 "));
  EXPECT_TRUE(Contains(text, "EDGE_SE3_STEREO 0 10 "));
  EXPECT_TRUE(Contains(text, "EDGE_SE3_PROJECT 0 10 "));
}

TEST(LandmarkIoTest, G2oLandmarksWithoutVerticesAreInitialized) {
  const std::string dir = TempDir();
  // Robot at (1, 2, 90 deg); the landmark 3 m ahead (world (1, 5)) seen as
  // a relative position, the second one by range and bearing.
  WriteText(dir + "/l.g2o",
            "VERTEX_SE2 0 1 2 1.5707963267948966\n"
            "EDGE_SE2_XY 0 7 3 0 1 0 1\n"
            "EDGE_SE2_RANGE_BEARING 0 8 2 1.5707963267948966 1 0 1\n");
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(dir + "/l.g2o", {}, &graph, &report, &error))
      << error;
  EXPECT_EQ(report.landmarks_initialized, 2);
  const std::vector<double>& a = graph.FindNode(Point2Key(7))->value;
  const std::vector<double>& b = graph.FindNode(Point2Key(8))->value;
  EXPECT_NEAR(a[0], 1.0, 1e-12);
  EXPECT_NEAR(a[1], 5.0, 1e-12);
  EXPECT_NEAR(b[0], -1.0, 1e-12);
  EXPECT_NEAR(b[1], 2.0, 1e-12);
  EXPECT_NEAR(graph.Chi2(), 0.0, 1e-20);
}

// Reading `text` fails with an error naming the line and containing `what`.
void ExpectG2oError(const std::string& text, int line,
                    const std::string& what) {
  const std::string dir = TempDir();
  const std::string path = dir + "/bad.g2o";
  WriteText(path, text);
  Graph graph;
  std::string error;
  EXPECT_FALSE(ReadPoseGraph(path, {}, &graph, nullptr, &error)) << text;
  EXPECT_TRUE(Contains(error, path + ":" + std::to_string(line) + ": "))
      << error;
  EXPECT_TRUE(Contains(error, what)) << error;
  EXPECT_EQ(graph.NumNodes(), 0u);
}

TEST(LandmarkIoTest, G2oBadLandmarkInputNamesTheLine) {
  const std::string pose = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n";
  ExpectG2oError(pose + "VERTEX_TRACKXYZ 1 0 0\n", 2, "fields");
  ExpectG2oError(pose + "EDGE_SE3_TRACKXYZ 0 1 5 1 2 3 1 0 0 1 0 1\n", 2,
                 "PARAMS_SE3OFFSET 5");
  ExpectG2oError(pose +
                     "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n"
                     "PARAMS_SE3OFFSET 0 1 0 0 0 0 0 1\n",
                 3, "duplicate PARAMS_SE3OFFSET");
  ExpectG2oError(pose + "PARAMS_STEREO 0 700 700 600 180 -0.5\n", 2,
                 "positive");
  ExpectG2oError(pose +
                     "PARAMS_PINHOLE 0 400 400 300 200 0 0 0 0\n"
                     "EDGE_SE3_PROJECT 0 1 0 10 20 1 0 -1\n",
                 3, "positive definite");
  ExpectG2oError(pose + "VERTEX_TRACKXYZ 0 1 2 3\nVERTEX_TRACKXYZ 0 1 2 3\n", 3,
                 "duplicate vertex");
  ExpectG2oError("VERTEX_SE2 0 0 0 0\nEDGE_SE2_XY 0 1 1 nan 1 0 1\n", 2,
                 "field");
}

TEST(LandmarkIoTest, PosesAndLandmarksHaveSeparateIdSpacesInG2o) {
  Graph graph;
  graph.AddNode(Pose2Key(3), {0, 0, 0});
  graph.AddNode(Point2Key(3), {1, 1});
  Factor f;
  std::string error;
  ASSERT_TRUE(MakeRelativePoint2(Pose2Key(3), Point2Key(3),
                                 Eigen::Vector2d(1, 1),
                                 Eigen::Matrix2d::Identity(), &f, &error));
  ASSERT_GE(graph.AddFactor(f), 0);
  ExpectG2oRoundTrip(graph);
  // A fixed landmark with a pose's id cannot be written: FIX is ambiguous.
  graph.SetFixed(Point2Key(3), true);
  const std::string dir = TempDir();
  EXPECT_FALSE(WriteG2o(dir + "/x.g2o", graph, &error));
  EXPECT_TRUE(Contains(error, "FIX")) << error;
  EXPECT_FALSE(Exists(dir + "/x.g2o"));
}

TEST(LandmarkIoTest, IsamRoundTripAndSquareRootInformation) {
  const std::string dir = TempDir();
  // R = [[2 1 0] [0 4 0] [0 0 10]]: Omega = R^T R.
  WriteText(dir + "/a.txt",
            "ODOMETRY 0 1 1 0 0.1 2 1 0 4 0 10\n"
            "LANDMARK 0 5 3 1 1.5 0.5 2\n"
            "LANDMARK 1 5 2 1.1 1.5 0 2\n");
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(dir + "/a.txt", {}, &graph, &report, &error))
      << error;
  ASSERT_EQ(graph.NumNodes(), 3u);
  ASSERT_EQ(graph.NumFactors(), 3u);
  EXPECT_EQ(report.landmarks_initialized, 1);
  const Factor& odo = graph.factors().begin()->second;
  Eigen::Matrix3d r;
  r << 2, 1, 0, 0, 4, 0, 0, 0, 10;
  EXPECT_EQ(odo.type, FactorType::kBetweenSE2);
  // iSAM's translation error is in the frame of i, ours in the frame of z:
  // Omega = J^T R^T R J, J = diag(Rot(0.1), 1) (isam_io.h).
  Eigen::Matrix3d jac = Eigen::Matrix3d::Identity();
  jac.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(0.1).toRotationMatrix();
  EXPECT_LT(
      (odo.information - jac.transpose() * r.transpose() * r * jac).norm(),
      1e-12);
  const Factor& lm = std::next(graph.factors().begin())->second;
  EXPECT_EQ(lm.type, FactorType::kRelativePoint2);
  EXPECT_EQ(lm.keys[1], Point2Key(5));
  // Pose 1 from odometry, landmark 5 from its first observation.
  const std::vector<double>& p = graph.FindNode(Point2Key(5))->value;
  EXPECT_NEAR(p[0], 3.0, 1e-12);
  EXPECT_NEAR(p[1], 1.0, 1e-12);

  ASSERT_TRUE(WriteIsam(dir + "/b.txt", graph, &error)) << error;
  Graph back;
  ASSERT_TRUE(ReadIsam(dir + "/b.txt", {}, &back, nullptr, &error)) << error;
  ASSERT_EQ(back.NumFactors(), graph.NumFactors());
  auto ib = back.factors().begin();
  for (const auto& [id, f] : graph.factors()) {
    EXPECT_EQ(f.type, ib->second.type);
    EXPECT_EQ(f.keys, ib->second.keys);
    EXPECT_EQ(f.measurement, ib->second.measurement);
    EXPECT_LT((f.information - ib->second.information).norm(),
              1e-13 * f.information.norm());
    ++ib;
  }
  for (const auto& [key, node] : graph.nodes()) {
    ASSERT_TRUE(back.HasNode(key));
    for (size_t k = 0; k < node->value.size(); ++k) {
      EXPECT_NEAR(node->value[k], back.FindNode(key)->value[k], 1e-12);
    }
  }
}

TEST(LandmarkIoTest, IsamBadInputNamesTheLine) {
  const std::string dir = TempDir();
  const struct {
    std::string text;
    int line;
    std::string what;
  } cases[] = {
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nEDGE3 0 1\n", 2,
       "EDGE3 needs 8 or 29 fields after the tag, found 2"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nPOINT3 0 1 1 2 3 1\n", 2,
       "POINT3 needs 5 or 11 fields after the tag, found 6"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nFOO 0 1\n", 2,
       "unknown iSAM record 'FOO'"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nCAMERA_STEREO 0 400 320 240 0.5\n", 2,
       "stereo record"},
      {"EDGE3 0 1 1 0 0 0 1.5707963267948966 0\n", 1, "Euler singularity"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nEDGE3 1 2 1 0 0 0 0 0\n", 2, "mix"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0\n", 1, "fields"},
      {"ODOMETRY 0 1 1 0 0 1 0 0 1 0 1\nLANDMARK 0 5 1 1 0 0 1\n", 2,
       "zero on its diagonal"},
  };
  for (const auto& c : cases) {
    WriteText(dir + "/bad.txt", c.text);
    Graph graph;
    std::string error;
    EXPECT_FALSE(ReadIsam(dir + "/bad.txt", {}, &graph, nullptr, &error));
    EXPECT_TRUE(
        Contains(error, dir + "/bad.txt:" + std::to_string(c.line) + ": "))
        << error;
    EXPECT_TRUE(Contains(error, c.what)) << error;
  }
}

TEST(LandmarkIoTest, ToroBearingRangeRoundTrip) {
  const std::string dir = TempDir();
  WriteText(dir + "/a.graph",
            "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n"
            "EDGE2 0 1 1 0 0 10 0 10 100 0 0\n"
            "BR 0 50 0.5 4 0.0349 0.1\nBR 1 50 0.9 3.5 0.0349 0.1\n");
  Graph graph;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(dir + "/a.graph", {}, &graph, nullptr, &error))
      << error;
  ASSERT_EQ(graph.NumFactors(), 3u);
  const Factor& br = std::next(graph.factors().begin())->second;
  EXPECT_EQ(br.type, FactorType::kRangeBearing2);
  EXPECT_EQ(br.measurement, Eigen::Vector2d(4.0, 0.5));
  EXPECT_NEAR(br.information(0, 0), 100.0, 1e-9);
  EXPECT_NEAR(br.information(1, 1), 1.0 / (0.0349 * 0.0349), 1e-6);
  const std::vector<double>& p = graph.FindNode(Point2Key(50))->value;
  EXPECT_NEAR(p[0], 4.0 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(p[1], 4.0 * std::sin(0.5), 1e-12);
  ASSERT_TRUE(WriteToro(dir + "/b.graph", graph, &error)) << error;
  Graph back;
  ASSERT_TRUE(ReadToro(dir + "/b.graph", {}, &back, nullptr, &error)) << error;
  ASSERT_EQ(back.NumFactors(), 3u);
  const Factor& br2 = std::next(back.factors().begin())->second;
  EXPECT_EQ(br2.measurement, br.measurement);
  EXPECT_LT((br2.information - br.information).norm(),
            1e-12 * br.information.norm());
  // Bad sigma.
  WriteText(dir + "/c.graph", "VERTEX2 0 0 0 0\nBR 0 5 0.5 4 0 0.1\n");
  Graph bad;
  EXPECT_FALSE(ReadToro(dir + "/c.graph", {}, &bad, nullptr, &error));
  EXPECT_TRUE(Contains(error, dir + "/c.graph:2: ")) << error;
}

TEST(LandmarkIoTest, StereoVoReadsTheThreeFilesAndRejectsBadLines) {
  const std::string dir = TempDir();
  WriteText(dir + "/cal.txt", "700 700 0 600 180 0.5\n");
  WriteText(dir + "/poses.txt",
            "1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
            "2 1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 1\n");
  // Point (1, 0.5, 10) in camera 1; camera 2 one metre further along z.
  const auto line = [](int pose, const Eigen::Vector3d& p) {
    const double ul = 700 * p.x() / p.z() + 600;
    const double ur = 700 * (p.x() - 0.5) / p.z() + 600;
    const double v = 700 * p.y() / p.z() + 180;
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "%d 7 %.17g %.17g %.17g %.17g %.17g %.17g\n", pose, ul, ur, v,
                  p.x(), p.y(), p.z());
    return std::string(buf);
  };
  WriteText(dir + "/f.txt", line(1, Eigen::Vector3d(1, 0.5, 10)) +
                                line(2, Eigen::Vector3d(1, 0.5, 9)));
  Graph graph;
  StereoVoReport report;
  std::string error;
  ASSERT_TRUE(ReadStereoVo(dir + "/f.txt", dir + "/cal.txt", dir + "/poses.txt",
                           &graph, &report, &error))
      << error;
  EXPECT_EQ(report.poses, 2);
  EXPECT_EQ(report.landmarks, 1);
  EXPECT_EQ(report.measurements, 2);
  const Key point = Point3Key(7 + kStereoVoLandmarkIdOffset);
  ASSERT_TRUE(graph.HasNode(point));
  EXPECT_NEAR(graph.Chi2(), 0.0, 1e-18);
  EXPECT_NEAR(CameraPixelErrors(graph).rms, 0.0, 1e-9);
  // Written as g2o and read back: same graph.
  ASSERT_TRUE(WriteG2o(dir + "/vo.g2o", graph, &error)) << error;
  Graph back;
  ASSERT_TRUE(ReadG2o(dir + "/vo.g2o", {}, &back, nullptr, &error)) << error;
  ExpectSameGraph(graph, back);

  WriteText(dir + "/bad.txt",
            line(1, Eigen::Vector3d(1, 0.5, 10)) + "3 7 1 2 3 4 5 6\n");
  Graph g2;
  EXPECT_FALSE(ReadStereoVo(dir + "/bad.txt", dir + "/cal.txt",
                            dir + "/poses.txt", &g2, nullptr, &error));
  EXPECT_TRUE(Contains(error, dir + "/bad.txt:2: unknown camera pose id 3"))
      << error;
  WriteText(dir + "/bad.txt", "1 7 1 2 3 4 5\n");
  EXPECT_FALSE(ReadStereoVo(dir + "/bad.txt", dir + "/cal.txt",
                            dir + "/poses.txt", &g2, nullptr, &error));
  EXPECT_TRUE(Contains(error, dir + "/bad.txt:1: ")) << error;
  WriteText(dir + "/cal2.txt", "700 700 0.1 600 180 0.5\n");
  EXPECT_FALSE(ReadStereoVo(dir + "/f.txt", dir + "/cal2.txt",
                            dir + "/poses.txt", &g2, nullptr, &error));
  EXPECT_TRUE(Contains(error, "cal2.txt:1: skew")) << error;
}

TEST(LandmarkIoTest, OptimizeFailsOnBadInputWithoutOutput) {
  const std::string dir = TempDir();
  WriteText(dir + "/bad.g2o",
            "VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 2 2\nEDGE_SE2_XY 0 1 1 1 1 0\n");
  const std::string log = dir + "/log.txt";
  EXPECT_NE(::slam::testing::RunSlam(
                "optimize -i " + dir + "/bad.g2o -o " + dir + "/out.g2o", log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), dir + "/bad.g2o:3: ")) << ReadText(log);
  EXPECT_FALSE(Exists(dir + "/out.g2o"));
}

TEST(LandmarkIoTest, OptimizeWritesLandmarksAndDrawsTheMap) {
  const std::string dir = TempDir();
  // Three poses along x, two landmarks seen from each (relative position,
  // exact), noisy odometry: the landmarks pull the poses straight.
  std::string text =
      "EDGE_SE2 0 1 1.1 0 0.05 100 0 0 100 0 100\n"
      "EDGE_SE2 1 2 0.9 0 -0.05 100 0 0 100 0 100\n";
  for (int i = 0; i < 3; ++i) {
    for (int j : {10, 11}) {
      const double lx = j == 10 ? 1.0 : 2.0, ly = j == 10 ? 2.0 : -2.0;
      text += "EDGE_SE2_XY " + std::to_string(i) + " " + std::to_string(j) +
              " " + std::to_string(lx - i) + " " + std::to_string(ly) +
              " 1000 0 1000\n";
    }
  }
  WriteText(dir + "/in.g2o", text);
  const std::string log = dir + "/log.txt";
  ASSERT_EQ(::slam::testing::RunSlam("optimize -i " + dir + "/in.g2o -o " +
                                         dir + "/out.g2o --plot " + dir +
                                         "/plots --robust_landmark huber:1",
                                     log),
            0)
      << ReadText(log);
  EXPECT_TRUE(Contains(ReadText(log), "landmarks: 2")) << ReadText(log);
  EXPECT_TRUE(Exists(dir + "/plots/map.png"));
  Graph out;
  std::string error;
  ASSERT_TRUE(ReadG2o(dir + "/out.g2o", {}, &out, nullptr, &error)) << error;
  ASSERT_TRUE(out.HasNode(Point2Key(10)));
  const std::vector<double>& l = out.FindNode(Point2Key(10))->value;
  EXPECT_NEAR(l[0], 1.0, 0.05);
  EXPECT_NEAR(l[1], 2.0, 0.05);
  EXPECT_EQ(out.NumFactors(), 8u);
}

// ---- iSAM's format as iSAM defines it (isam/Loader.cpp, slam2d.h,
// slam3d.h): handmade fixtures compared with iSAM's own objective. ----

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// Upper triangle of an N x N upper-triangular R, row-major, as text.
std::string UpperText(const Eigen::MatrixXd& r) {
  std::string out;
  for (int row = 0; row < r.rows(); ++row) {
    for (int col = row; col < r.cols(); ++col) out += " " + Num(r(row, col));
  }
  return out;
}

// A random upper-triangular R with a positive diagonal and off-diagonals.
Eigen::MatrixXd RandomSqrt(int n, Rng* rng) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, n);
  for (int row = 0; row < n; ++row) {
    r(row, row) = rng->Uniform(1.0, 20.0);
    for (int col = row + 1; col < n; ++col) r(row, col) = rng->Uniform(-3, 3);
  }
  return r;
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

// ODOMETRY/EDGE2/Constraint2 with large turns and full square-root
// information: our objective is iSAM's (translation error in the frame of
// i, not of z) to rounding, at any values; LANDMARK ids have their own id
// space (cityTrees10000 numbers poses and landmarks from 0).
TEST(LandmarkIoTest, IsamOdometryObjectiveIsIsamsAndLandmarkIdsAreSeparate) {
  Rng rng(13);
  struct Edge {
    int i, j;
    Eigen::Vector3d z;
    Eigen::MatrixXd r;
  };
  std::vector<Edge> edges;
  const char* tags[] = {"ODOMETRY", "EDGE2", "Constraint2", "ODOMETRY"};
  std::string text;
  for (int k = 0; k < 4; ++k) {
    Edge e{k, k + 1,
           Eigen::Vector3d(rng.Uniform(-2, 2), rng.Uniform(-2, 2),
                           rng.Uniform(-3, 3)),
           RandomSqrt(3, &rng)};
    if (k == 3) e.i = 0;  // A loop closure 0 -> 4.
    text += std::string(tags[k]) + " " + std::to_string(e.i) + " " +
            std::to_string(e.j) + " " + Num(e.z[0]) + " " + Num(e.z[1]) + " " +
            Num(e.z[2]) + UpperText(e.r) + "\n";
    edges.push_back(e);
  }
  // Landmark 1 shares its number with pose 1.
  text += "LANDMARK 1 1 2.5 -1 3 0.5 2\nLANDMARK 2 1 1.5 0.5 3 0 2\n";
  const std::string dir = TempDir();
  WriteText(dir + "/odo.txt", text);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(dir + "/odo.txt", {}, &graph, &report, &error))
      << error;
  ASSERT_EQ(graph.NumFactors(), 6u);
  EXPECT_TRUE(graph.HasNode(Pose2Key(1)));
  EXPECT_TRUE(graph.HasNode(Point2Key(1)));
  EXPECT_EQ(report.landmarks_initialized, 1);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<Eigen::Vector3d> x(5);
    for (int k = 0; k < 5; ++k) {
      x[k] = Eigen::Vector3d(rng.Uniform(-5, 5), rng.Uniform(-5, 5),
                             rng.Uniform(-3, 3));
      std::copy(x[k].data(), x[k].data() + 3,
                graph.FindNode(Pose2Key(k))->value.begin());
    }
    // iSAM's Pose2d_Pose2d_Factor: e = (x_i^-1 x_j) - z, angle wrapped.
    double isam_chi2 = 0.0;
    for (const Edge& e : edges) {
      const Eigen::Matrix2d ri =
          Eigen::Rotation2Dd(x[e.i][2]).toRotationMatrix();
      Eigen::Vector3d err;
      err.head<2>() = ri.transpose() * (x[e.j].head<2>() - x[e.i].head<2>()) -
                      e.z.head<2>();
      err[2] = WrapAngle(x[e.j][2] - x[e.i][2] - e.z[2]);
      isam_chi2 += (e.r * err).squaredNorm();
    }
    double chi2 = 0.0;
    for (const auto& [id, f] : graph.factors()) {
      double c = 0.0;
      ASSERT_TRUE(graph.FactorChi2(f, &c));
      if (f.type == FactorType::kBetweenSE2) chi2 += c;
    }
    EXPECT_NEAR(chi2, isam_chi2, 1e-10 * isam_chi2);
  }
}

// iSAM's Pose3d_Pose3d_Factor objective: e = vec(x_i^-1 x_j) - vec(z) over
// (t, roll, pitch, yaw) in the file's order, angles wrapped.
double IsamEdge3Chi2(const Pose3& xi, const Pose3& xj, const Pose3& z,
                     const Eigen::MatrixXd& r) {
  const Pose3 pred = xi.Inverse() * xj;
  Eigen::VectorXd err(6);
  err.head<3>() = pred.t - z.t;
  const Eigen::Vector3d a = RpyFromQuaternion(pred.q);
  const Eigen::Vector3d b = RpyFromQuaternion(z.q);
  for (int k = 0; k < 3; ++k) err[3 + k] = WrapAngle(a[k] - b[k]);
  return (r * err).squaredNorm();
}

Pose3 PerturbPose(const Pose3& x, double size, Rng* rng) {
  const Eigen::Vector3d w = size * rng->Normal3();
  return Pose3(
      x.t + size * rng->Normal3(),
      (x.q * Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized())))
          .normalized());
}

// EDGE3 (iSAM's sphere/torus files): square-root information over (t, roll,
// pitch, yaw) with off-diagonal entries, one edge written from the higher to
// the lower id, one without information (identity); POINT3 with and without
// information. Near the measurements our objective agrees with iSAM's to
// first order (relative 1e-3 for perturbations of 1e-4); read as TORO's
// information, or with the Euler angles' scale alone, it is off by O(1).
TEST(LandmarkIoTest, IsamEdge3AndPoint3MatchIsamsObjective) {
  Rng rng(31);
  std::vector<Pose3> truth(4);
  for (int k = 0; k < 4; ++k) {
    truth[k] = Pose3(2.0 * rng.Normal3(),
                     QuaternionFromRpy(rng.Uniform(-1, 1), rng.Uniform(-1, 1),
                                       rng.Uniform(-3, 3)));
  }
  struct Edge {
    int i, j;  // As written in the file.
    bool with_sqrt;
    Eigen::MatrixXd r;
  };
  const Edge edges[] = {{0, 1, true, RandomSqrt(6, &rng)},
                        {2, 1, true, RandomSqrt(6, &rng)},
                        {2, 3, false, Eigen::MatrixXd::Identity(6, 6)},
                        {0, 3, true, RandomSqrt(6, &rng)}};
  std::string text;
  for (const Edge& e : edges) {
    const Pose3 z = truth[e.i].Inverse() * truth[e.j];
    const Eigen::Vector3d rpy = RpyFromQuaternion(z.q);
    text += "EDGE3 " + std::to_string(e.i) + " " + std::to_string(e.j);
    for (double v : {z.t[0], z.t[1], z.t[2], rpy[0], rpy[1], rpy[2]}) {
      text += " " + Num(v);
    }
    text += (e.with_sqrt ? UpperText(e.r) : "") + "\n";
  }
  const Eigen::Vector3d point(1.0, -2.0, 0.5);
  const Eigen::MatrixXd rp = RandomSqrt(3, &rng);
  for (int pose : {0, 1}) {
    const Eigen::Vector3d m =
        truth[pose].q.conjugate() * (point - truth[pose].t);
    text += "POINT3 " + std::to_string(pose) + " 1 " + Num(m[0]) + " " +
            Num(m[1]) + " " + Num(m[2]) + (pose == 0 ? UpperText(rp) : "") +
            "\n";
  }
  const std::string dir = TempDir();
  WriteText(dir + "/sphere.txt", text);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(dir + "/sphere.txt", {}, &graph, &report, &error))
      << error;
  ASSERT_EQ(graph.NumFactors(), 6u);
  EXPECT_TRUE(report.warnings.empty());  // POINT3 says it is iSAM's.
  EXPECT_TRUE(graph.HasNode(Pose3Key(1)));
  EXPECT_TRUE(graph.HasNode(Point3Key(1)));
  int k = 0;
  for (const auto& [id, f] : graph.factors()) {
    if (f.type == FactorType::kBetweenSE3) {
      // Lower id first, as iSAM keeps its edges.
      EXPECT_LT(f.keys[0].id, f.keys[1].id);
    } else {
      ASSERT_EQ(f.type, FactorType::kRelativePoint3);
      EXPECT_EQ(f.keys[1], Point3Key(1));
      const Eigen::MatrixXd expected =
          k == 4 ? Eigen::MatrixXd(rp.transpose() * rp)
                 : Eigen::MatrixXd::Identity(3, 3);
      EXPECT_LT((f.information - expected).norm(), 1e-12 * expected.norm());
    }
    ++k;
  }
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<Pose3> x(4);
    for (int n = 0; n < 4; ++n) {
      x[n] = PerturbPose(truth[n], 1e-4, &rng);
      Node* node = graph.FindNode(Pose3Key(n));
      std::copy(x[n].t.data(), x[n].t.data() + 3, node->value.begin());
      std::copy(x[n].q.coeffs().data(), x[n].q.coeffs().data() + 4,
                node->value.begin() + 3);
    }
    double isam_chi2 = 0.0;
    for (const Edge& e : edges) {
      const Pose3 z = truth[e.i].Inverse() * truth[e.j];
      isam_chi2 += e.i < e.j ? IsamEdge3Chi2(x[e.i], x[e.j], z, e.r)
                             : IsamEdge3Chi2(x[e.j], x[e.i], z.Inverse(), e.r);
    }
    double chi2 = 0.0;
    for (const auto& [id, f] : graph.factors()) {
      double c = 0.0;
      ASSERT_TRUE(graph.FactorChi2(f, &c));
      if (f.type == FactorType::kBetweenSE3) chi2 += c;
    }
    EXPECT_NEAR(chi2, isam_chi2, 1e-3 * isam_chi2);
  }
  // EDGE3 lines alone (iSAM's sphere400.txt) named .txt are iSAM's, with a
  // warning; named .graph, TORO's (information, not its root).
  const std::string edge = text.substr(0, text.find('\n') + 1);
  WriteText(dir + "/edge.txt", edge);
  Graph isam;
  ASSERT_TRUE(ReadPoseGraph(dir + "/edge.txt", {}, &isam, &report, &error))
      << error;
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(Contains(report.warnings[0], "read as iSAM"));
  WriteText(dir + "/sphere.graph", edge);
  Graph toro;
  ASSERT_TRUE(ReadPoseGraph(dir + "/sphere.graph", {}, &toro, &report, &error))
      << error;
  const Factor& first = toro.factors().begin()->second;
  EXPECT_NEAR(first.information(0, 0), edges[0].r(0, 0), 1e-12);
}

}  // namespace
}  // namespace slam
