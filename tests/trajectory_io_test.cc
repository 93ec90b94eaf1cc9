// Tests of datasets/trajectory_io: each format's round trip, detection, and
// malformed input (errors naming the file and line); real files read in place.
#include "datasets/trajectory_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/graph.h"
#include "core/keys.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::WriteText;

Trajectory Sample() {
  Trajectory t;
  for (int i = 0; i < 25; ++i) {
    StampedPose p;
    p.stamp = 1305031102175304000ll + i * 33333333ll;  // Not whole seconds.
    const Eigen::Quaterniond q(Eigen::AngleAxisd(
        0.1 * i, Eigen::Vector3d(0.3, -0.5, 1.0).normalized()));
    p.pose =
        Pose3(Eigen::Vector3d(0.1 * i, -2.0 + 0.01 * i * i, 1.0 / (i + 1)), q);
    t.push_back(p);
  }
  return t;
}

void ExpectSamePoses(const Trajectory& a, const Trajectory& b, double tol,
                     bool same_stamps = true) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    if (same_stamps) {
      EXPECT_EQ(a[i].stamp, b[i].stamp) << i;
    }
    EXPECT_LT((a[i].pose.t - b[i].pose.t).norm(), tol) << i;
    EXPECT_LT(a[i].pose.q.angularDistance(b[i].pose.q), tol) << i;
  }
}

// --------------------------------------------------------------------- stamps

TEST(StampTest, DecimalSecondsAreExactToTheNanosecond) {
  TimeNs t = 0;
  ASSERT_TRUE(ParseStampSeconds("1305031102.175304", &t));
  EXPECT_EQ(t, 1305031102175304000ll);  // A double would be 256 ns off here.
  ASSERT_TRUE(ParseStampSeconds("1403636580.8385556479", &t));
  EXPECT_EQ(t, 1403636580838555648ll);  // Rounded at the ninth decimal.
  ASSERT_TRUE(ParseStampSeconds("-0.5", &t));
  EXPECT_EQ(t, -500000000ll);
  ASSERT_TRUE(ParseStampSeconds("1.037359e-01", &t));
  EXPECT_EQ(t, 103735900ll);
  ASSERT_TRUE(ParseStampSeconds("42", &t));
  EXPECT_EQ(t, 42000000000ll);
  EXPECT_FALSE(ParseStampSeconds("12a", &t));
  EXPECT_FALSE(ParseStampSeconds("", &t));
  EXPECT_EQ(FormatStampSeconds(1305031102175304000ll), "1305031102.175304000");
  EXPECT_EQ(FormatStampSeconds(-1500000000ll), "-1.500000000");
}

// ------------------------------------------------------------------------ TUM

TEST(TumTest, RoundTripIsExact) {
  const std::string dir = testing::TempDir();
  const std::string path = dir + "/t.tum";
  const Trajectory t = Sample();
  std::string error;
  ASSERT_TRUE(WriteTrajectory(path, t, TrajectoryFormat::kTum, &error))
      << error;
  Trajectory back;
  ASSERT_TRUE(ReadTumTrajectory(path, &back, &error)) << error;
  ExpectSamePoses(t, back, 1e-15);
  TrajectoryFormat f;
  ASSERT_TRUE(DetectTrajectoryFormat(path, &f, &error)) << error;
  EXPECT_EQ(f, TrajectoryFormat::kTum);
  // No temporary file left behind.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(TumTest, NanosecondStampsAreRejectedWithAHint) {
  const std::string path = testing::TempDir() + "/ns.txt";
  WriteText(path,
            "# t x y z qx qy qz qw\n"
            "1403636580838555648 1 2 3 0 0 0 1\n");
  Trajectory t;
  std::string error;
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":2:"), std::string::npos) << error;
  EXPECT_NE(error.find("nanoseconds"), std::string::npos) << error;
  EXPECT_NE(error.find("1e9"), std::string::npos) << error;
}

TEST(TumTest, MalformedLinesNameFileAndLine) {
  const std::string path = testing::TempDir() + "/bad.txt";
  std::string error;
  Trajectory t;
  WriteText(path, "1.0 0 0 0 0 0 0 1\n\n2.0 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":3: expected 8 values"), std::string::npos)
      << error;
  WriteText(path, "1.0 0 0 0 0 0 0 1\n2.0 0 x 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":2: field 3 ('x')"), std::string::npos) << error;
  WriteText(path, "1.0 0 0 0 0 0 0 0\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find("zero length"), std::string::npos) << error;
  WriteText(path, "1.0 0 0 nan 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  WriteText(path, "# only a comment\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find("no poses"), std::string::npos) << error;
  EXPECT_FALSE(ReadTumTrajectory(path + ".missing", &t, &error));
  EXPECT_NE(error.find(".missing: cannot open"), std::string::npos) << error;
}

TEST(TumTest, DuplicateAndDecreasingStampsAreErrors) {
  const std::string path = testing::TempDir() + "/order.txt";
  Trajectory t;
  std::string error;
  WriteText(path,
            "1.0 0 0 0 0 0 0 1\n# c\n2.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":4:"), std::string::npos) << error;
  EXPECT_NE(error.find("duplicate"), std::string::npos) << error;
  EXPECT_NE(error.find("line 3"), std::string::npos) << error;
  WriteText(path, "2.0 0 0 0 0 0 0 1\n1.5 0 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTumTrajectory(path, &t, &error));
  EXPECT_NE(error.find("before"), std::string::npos) << error;
}

TEST(TumTest, DuplicateStampsAreKeptWithAWarningWhenAllowed) {
  const std::string path = testing::TempDir() + "/dup.txt";
  WriteText(path,
            "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n"
            "3.10 2 0 0 0 0 0 1\n3.10 3 0 0 0 0 0 1\n");
  TrajectoryReadOptions options;
  TrajectoryData data;
  std::string error;
  EXPECT_FALSE(ReadTrajectory(path, options, &data, &error));
  options.allow_duplicate_stamps = true;
  ASSERT_TRUE(ReadTrajectory(path, options, &data, &error)) << error;
  EXPECT_EQ(data.poses.size(), 5u);
  EXPECT_EQ(data.duplicate_stamps, 2u);
  EXPECT_NE(data.warning.find("2 duplicate stamps (first: " + path +
                              ":3: timestamp 2.000000000 s is a duplicate of "
                              "the one on line 2)"),
            std::string::npos)
      << data.warning;
  // The seconds are the doubles of the text, as evo parses them.
  ASSERT_EQ(data.seconds.size(), 5u);
  EXPECT_EQ(data.seconds[3], 3.10);
  // Decreasing stamps stay an error unless allowed too.
  WriteText(path, "2.0 0 0 0 0 0 0 1\n1.5 0 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadTrajectory(path, options, &data, &error));
  EXPECT_NE(error.find("before"), std::string::npos) << error;
  options.allow_unsorted_stamps = true;
  ASSERT_TRUE(ReadTrajectory(path, options, &data, &error)) << error;
  EXPECT_EQ(data.unsorted_stamps, 1u);
  EXPECT_NE(data.warning.find("1 decreasing stamp (first: " + path +
                              ":2: timestamp 1.500000000 s is before the one "
                              "on line 1)"),
            std::string::npos)
      << data.warning;
  EXPECT_EQ(data.poses[1].stamp, 1500000000);  // File order kept.
}

TEST(TumTest, QuaternionsAreNormalized) {
  const std::string path = testing::TempDir() + "/q.txt";
  WriteText(path, "0.5 1 2 3 0 0 0 2\n");
  Trajectory t;
  std::string error;
  ASSERT_TRUE(ReadTumTrajectory(path, &t, &error)) << error;
  EXPECT_NEAR(t[0].pose.q.norm(), 1.0, 1e-15);
  EXPECT_EQ(t[0].stamp, 500000000ll);
}

// ---------------------------------------------------------------------- KITTI

TEST(KittiTest, RoundTripWithAndWithoutTimes) {
  const std::string dir = testing::TempDir();
  const Trajectory t = Sample();
  std::string error;
  ASSERT_TRUE(
      WriteTrajectory(dir + "/poses.txt", t, TrajectoryFormat::kKitti, &error))
      << error;
  ASSERT_TRUE(WriteKittiTimes(dir + "/times.txt", t, &error)) << error;
  Trajectory back;
  bool has_stamps = true;
  ASSERT_TRUE(
      ReadKittiPoses(dir + "/poses.txt", "", &back, &has_stamps, &error))
      << error;
  EXPECT_FALSE(has_stamps);
  ExpectSamePoses(t, back, 1e-12, false);
  EXPECT_EQ(back[3].stamp, 3 * kNanosecondsPerSecond);  // The index.
  ASSERT_TRUE(ReadKittiPoses(dir + "/poses.txt", dir + "/times.txt", &back,
                             &has_stamps, &error))
      << error;
  EXPECT_TRUE(has_stamps);
  ExpectSamePoses(t, back, 1e-12, true);
  TrajectoryFormat f;
  ASSERT_TRUE(DetectTrajectoryFormat(dir + "/poses.txt", &f, &error));
  EXPECT_EQ(f, TrajectoryFormat::kKitti);
}

TEST(KittiTest, TheEvaluationGetsTheMatricesAsRead) {
  // 7 significant digits: 1e-7 off SO(3). Pose3 holds the nearest rotation,
  // the evaluation the matrix as written (as evo and the devkit).
  const std::string path = testing::TempDir() + "/raw.txt";
  WriteText(path,
            "1.000000 0 0 0 0 1 0 0 0 0 1 0\n"
            "0.9999999 0.0001234 0 1.5 -0.0001234 1.000000 0 0 0 0 1.0000001 "
            "0\n");
  TrajectoryData data;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(path, {}, &data, &error)) << error;
  ASSERT_EQ(data.matrices.size(), 2u);
  const EvalTrajectory e = ToEvalTrajectory(data);
  Eigen::Matrix3d want;
  want << 0.9999999, 0.0001234, 0, -0.0001234, 1.000000, 0, 0, 0, 1.0000001;
  EXPECT_EQ(e.poses[1].r, want);
  EXPECT_EQ(e.poses[1].t, Eigen::Vector3d(1.5, 0, 0));
  EXPECT_GT((data.poses[1].pose.q.toRotationMatrix() - want).norm(), 5e-8);
  EXPECT_EQ(e.seconds[1], 1.0);  // The index, without times.
}

TEST(KittiTest, MalformedInput) {
  const std::string dir = testing::TempDir();
  const std::string path = dir + "/k.txt";
  Trajectory t;
  bool has = false;
  std::string error;
  WriteText(path, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_FALSE(ReadKittiPoses(path, "", &t, &has, &error));
  EXPECT_NE(error.find(path + ":2: expected 12 values"), std::string::npos)
      << error;
  WriteText(path, "2 0 0 0 0 1 0 0 0 0 1 0\n");  // Not a rotation.
  EXPECT_FALSE(ReadKittiPoses(path, "", &t, &has, &error));
  EXPECT_NE(error.find(path + ":1: the 3x3 part is not a rotation"),
            std::string::npos)
      << error;
  WriteText(path, "-1 0 0 0 0 1 0 0 0 0 1 0\n");  // A reflection.
  EXPECT_FALSE(ReadKittiPoses(path, "", &t, &has, &error));
  WriteText(path, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  WriteText(dir + "/times.txt", "0.0\n");
  EXPECT_FALSE(ReadKittiPoses(path, dir + "/times.txt", &t, &has, &error));
  EXPECT_NE(error.find("1 stamps for 2 poses"), std::string::npos) << error;
  WriteText(dir + "/times.txt", "0.0\n0.0\n");
  EXPECT_FALSE(ReadKittiPoses(path, dir + "/times.txt", &t, &has, &error));
  EXPECT_NE(error.find("times.txt:2:"), std::string::npos) << error;
}

// ---------------------------------------------------------------------- EuRoC

TEST(EurocTest, GroundTruthCsvWithWFirstQuaternions) {
  const std::string path = testing::FixturePath("euroc_groundtruth_sample.csv");
  TrajectoryData d;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(path, {}, &d, &error)) << error;
  EXPECT_EQ(d.format, TrajectoryFormat::kEuroc);
  ASSERT_EQ(d.poses.size(), 3u);
  EXPECT_EQ(d.poses[0].stamp, 1403636580838555648ll);
  EXPECT_DOUBLE_EQ(d.poses[0].pose.t.x(), 4.688319);
  // q_RS_w first: 0.534108, -0.153029, -0.827383, -0.082152 (normalized).
  const Eigen::Quaterniond q = d.poses[0].pose.q;
  const double n = std::sqrt(0.534108 * 0.534108 + 0.153029 * 0.153029 +
                             0.827383 * 0.827383 + 0.082152 * 0.082152);
  EXPECT_NEAR(q.w(), 0.534108 / n, 1e-12);
  EXPECT_NEAR(q.x(), -0.153029 / n, 1e-12);
  EXPECT_NEAR(q.y(), -0.827383 / n, 1e-12);
  EXPECT_NEAR(q.z(), -0.082152 / n, 1e-12);
}

TEST(EurocTest, RoundTripAndFolderLayout) {
  const std::string dir = testing::TempDir();
  std::filesystem::create_directories(dir +
                                      "/mav0/state_groundtruth_estimate0");
  const std::string path = dir + "/mav0/state_groundtruth_estimate0/data.csv";
  const Trajectory t = Sample();
  std::string error;
  ASSERT_TRUE(WriteTrajectory(path, t, TrajectoryFormat::kEuroc, &error))
      << error;
  TrajectoryData d;
  ASSERT_TRUE(ReadTrajectory(dir, {}, &d, &error)) << error;  // The folder.
  EXPECT_EQ(d.path, path);
  ExpectSamePoses(t, d.poses, 1e-15);
}

TEST(EurocTest, MalformedInput) {
  const std::string path = testing::TempDir() + "/e.csv";
  Trajectory t;
  std::string error;
  WriteText(path,
            "#timestamp,x,y,z,qw,qx,qy,qz\n1403636580.838,1,2,3,1,0,0,0\n");
  EXPECT_FALSE(ReadEurocTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":2:"), std::string::npos) << error;
  EXPECT_NE(error.find("integer nanoseconds"), std::string::npos) << error;
  WriteText(path, "timestamp,x,y,z,qw,qx,qy,qz\n1,1,2,3,1,0,0\n");
  EXPECT_FALSE(ReadEurocTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":2: expected at least 8"), std::string::npos)
      << error;
  WriteText(path,
            "timestamp,x,y,z,qw,qx,qy,qz\n5,1,2,3,1,0,0,0\n4,1,2,3,1,0,0,0\n");
  EXPECT_FALSE(ReadEurocTrajectory(path, &t, &error));
  EXPECT_NE(error.find(path + ":3:"), std::string::npos) << error;
}

// ------------------------------------------------------------------------ g2o

TEST(G2oTest, PoseVerticesSortedByIdWithIdStamps) {
  TrajectoryData d;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(testing::FixturePath("trajectory_vertices.g2o"),
                             {}, &d, &error))
      << error;
  EXPECT_EQ(d.format, TrajectoryFormat::kG2o);
  ASSERT_EQ(d.poses.size(), 3u);  // VERTEX_XY ignored.
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(d.poses[i].stamp, i * kNanosecondsPerSecond);
  }
  EXPECT_DOUBLE_EQ(d.poses[2].pose.t.x(), 2.0);
  EXPECT_NEAR(d.poses[2].pose.q.angularDistance(Eigen::Quaterniond::Identity()),
              M_PI / 2, 1e-12);
}

TEST(G2oTest, RoundTripAndErrors) {
  const std::string dir = testing::TempDir();
  Trajectory t = Sample();
  for (size_t i = 0; i < t.size(); ++i)
    t[i].stamp = (10 + 2 * i) * kNanosecondsPerSecond;
  std::string error;
  ASSERT_TRUE(
      WriteTrajectory(dir + "/v.g2o", t, TrajectoryFormat::kG2o, &error));
  Trajectory back;
  ASSERT_TRUE(ReadG2oPoses(dir + "/v.g2o", &back, &error)) << error;
  ExpectSamePoses(t, back, 1e-15);
  WriteText(dir + "/dup.g2o", "VERTEX_SE2 1 0 0 0\nVERTEX_SE2 1 1 0 0\n");
  EXPECT_FALSE(ReadG2oPoses(dir + "/dup.g2o", &back, &error));
  EXPECT_NE(error.find("dup.g2o:2:"), std::string::npos) << error;
  WriteText(dir + "/short.g2o", "VERTEX_SE3:QUAT 1 0 0 0 0 0 1\n");
  EXPECT_FALSE(ReadG2oPoses(dir + "/short.g2o", &back, &error));
  EXPECT_NE(error.find("short.g2o:1:"), std::string::npos) << error;
  EXPECT_FALSE(
      ReadG2oPoses(testing::FixturePath("g2o_no_vertices.g2o"), &back, &error));
  EXPECT_NE(error.find("no VERTEX_SE2"), std::string::npos) << error;
}

TEST(G2oTest, TrajectoryFromGraphUsesIds) {
  Graph g;
  ASSERT_NE(g.AddNode(Pose2Key(5), {1.0, 2.0, 0.5}), nullptr);
  ASSERT_NE(g.AddNode(Pose2Key(2), {0.0, 1.0, 0.0}), nullptr);
  ASSERT_NE(g.AddNode(Point2Key(3), {9.0, 9.0}), nullptr);
  Trajectory t;
  std::string error;
  ASSERT_TRUE(TrajectoryFromGraph(g, false, &t, &error)) << error;
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].stamp, 2 * kNanosecondsPerSecond);
  EXPECT_EQ(t[1].stamp, 5 * kNanosecondsPerSecond);
  EXPECT_DOUBLE_EQ(t[1].pose.t.y(), 2.0);
  ASSERT_NE(g.AddNode(Pose3Key(5), {0, 0, 0, 0, 0, 0, 1}), nullptr);
  EXPECT_FALSE(TrajectoryFromGraph(g, false, &t, &error));
}

// fuzz_trajectory (CI): a vertex id of 44444444444444 overflowed int64 when
// made a stamp in nanoseconds. It is an error naming the id.
TEST(G2oTest, TrajectoryFromGraphRejectsAnIdBeyondStamps) {
  Graph g;
  ASSERT_NE(g.AddNode(Pose2Key(44444444444444), {0.0, 4.0, 0.0}), nullptr);
  Trajectory t;
  std::string error;
  EXPECT_FALSE(TrajectoryFromGraph(g, false, &t, &error));
  EXPECT_NE(error.find("44444444444444"), std::string::npos) << error;
  Graph ok;
  ASSERT_NE(ok.AddNode(Pose2Key(9223372036), {0.0, 4.0, 0.0}), nullptr);
  ASSERT_TRUE(TrajectoryFromGraph(ok, false, &t, &error)) << error;
  EXPECT_EQ(t[0].stamp, 9223372036 * kNanosecondsPerSecond);
}

// ------------------------------------------------------------------ detection

TEST(DetectTest, UnknownContentIsAnError) {
  const std::string path = testing::TempDir() + "/x.txt";
  WriteText(path, "# header\n1 2 3 4 5\n");
  TrajectoryFormat f;
  std::string error;
  EXPECT_FALSE(DetectTrajectoryFormat(path, &f, &error));
  EXPECT_NE(error.find(path + ":2: cannot tell"), std::string::npos) << error;
  TrajectoryFormat parsed;
  EXPECT_TRUE(ParseTrajectoryFormat("euroc", &parsed));
  EXPECT_EQ(parsed, TrajectoryFormat::kEuroc);
  EXPECT_FALSE(ParseTrajectoryFormat("csv", &parsed));
}

TEST(WriteTest, UnwritableTargetFailsCleanly) {
  std::string error;
  EXPECT_FALSE(WriteTrajectory("/nonexistent_dir_slam/t.txt", Sample(),
                               TrajectoryFormat::kTum, &error));
  EXPECT_NE(error.find("/nonexistent_dir_slam/t.txt"), std::string::npos);
}

// ------------------------------------------------------------------ real data

TEST(RealTrajectoryFilesTest, EvoTestData) {
  const std::string dir = testing::DatasetPath("trajectories_evo");
  SLAM_REQUIRE_DATASET(dir + "/KITTI_00_gt.txt");
  TrajectoryReadOptions o;
  o.kitti_times_path = dir + "/KITTI_00_gt_times.txt";
  TrajectoryData d;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(dir + "/KITTI_00_gt.txt", o, &d, &error)) << error;
  EXPECT_EQ(d.format, TrajectoryFormat::kKitti);
  EXPECT_TRUE(d.has_stamps);
  ASSERT_EQ(d.poses.size(), 4541u);
  EXPECT_EQ(d.poses[1].stamp, 103735900ll);  // 1.037359e-01 s.
  // Row 2 of the file: t = (-4.690294e-02, -2.839928e-02, 8.586941e-01).
  EXPECT_DOUBLE_EQ(d.poses[1].pose.t.z(), 8.586941e-01);
  ASSERT_TRUE(ReadTrajectory(dir + "/KITTI_00_ORB.txt", {}, &d, &error))
      << error;
  EXPECT_FALSE(d.has_stamps);
  EXPECT_EQ(d.poses.size(), 4541u);
  ASSERT_TRUE(
      ReadTrajectory(dir + "/freiburg1_xyz-groundtruth.txt", {}, &d, &error))
      << error;
  EXPECT_EQ(d.format, TrajectoryFormat::kTum);
  EXPECT_EQ(d.poses.size(), 3000u);
  EXPECT_EQ(d.poses[0].stamp, 1305031098665900000ll);  // 1305031098.6659
  ASSERT_TRUE(
      ReadTrajectory(dir + "/freiburg1_xyz-rgbdslam.txt", {}, &d, &error))
      << error;
  EXPECT_EQ(d.poses.size(), 788u);
  EXPECT_EQ(d.poses[0].stamp, 1305031102160407000ll);
}

TEST(RealTrajectoryFilesTest, G2oPoseNodes) {
  const std::string path = testing::DatasetPath("posegraph_2d/MIT.g2o");
  SLAM_REQUIRE_DATASET(path);
  TrajectoryData d;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(path, {}, &d, &error)) << error;
  EXPECT_EQ(d.format, TrajectoryFormat::kG2o);
  EXPECT_EQ(d.poses.size(), 808u);
}

}  // namespace
}  // namespace slam
