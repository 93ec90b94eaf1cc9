// Landmark SLAM and bundle adjustment on the shared real data (skipped with a
// message where it is absent):
//   * Victoria Park (iSAM format): loads with its published counts and
//     converges with a robust kernel on the landmark factors;
//   * KITTI stereo VO (GTSAM's StereoVOExample_large files): bundle
//     adjustment of all cameras and points converges and the reprojection
//     RMS drops; the camera poses are camera-to-world;
//   * GTSAM's g2o landmark files load with the values they hold, and the
//     EDGE_SE3_TRACKXYZ error follows g2o's sensor-offset semantics;
//   * GTSAM's example.graph (TORO with BR lines) optimizes.
#include <Eigen/Core>
#include <cmath>
#include <string>

#include "core/graph.h"
#include "core/optimizer.h"
#include "datasets/g2o_io.h"
#include "datasets/isam_io.h"
#include "datasets/stereo_vo_io.h"
#include "factors/landmark_factors.h"
#include "factors/robust_kernels.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::DatasetPath;

OptimizerOptions Quiet() {
  OptimizerOptions options;
  options.verbose = false;
  options.max_iterations = 300;
  return options;
}

void SetLandmarkKernel(const std::string& text, Graph* graph) {
  RobustKernelSpec spec;
  std::string error;
  ASSERT_TRUE(ParseRobustKernel(text, &spec, &error)) << error;
  std::vector<FactorId> ids;
  for (const auto& [id, f] : graph->factors()) {
    if (IsLandmarkFactor(f.type)) ids.push_back(id);
  }
  for (FactorId id : ids) graph->SetLoss(id, MakeLoss(spec));
}

TEST(LandmarkDataTest, VictoriaParkConvergesWithRobustLandmarks) {
  const std::string path = DatasetPath("isam_format/isam_victoriaPark.txt");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, &report, &error)) << error;
  int poses = 0, points = 0, odometry = 0, landmark = 0;
  for (const auto& [key, node] : graph.nodes()) {
    poses += key.kind == NodeKind::kPose2;
    points += key.kind == NodeKind::kPoint2;
  }
  for (const auto& [id, f] : graph.factors()) {
    odometry += f.type == FactorType::kBetweenSE2;
    landmark += f.type == FactorType::kRelativePoint2;
  }
  // isam_data_README.txt: 6969 poses, 151 landmarks, 3640 landmark
  // measurements, 6968 odometry constraints.
  EXPECT_EQ(poses, 6969);
  EXPECT_EQ(points, 151);
  EXPECT_EQ(odometry, 6968);
  EXPECT_EQ(landmark, 3640);
  EXPECT_EQ(report.landmarks_initialized, 151);
  // DCS on the landmark factors and non-monotonic steps (as
  // configs/benchmarks/landmarks.yaml): Huber and plain least squares stop
  // in poorer minima from dead reckoning (chi2 2.2e5 and 5.0e5).
  SetLandmarkKernel("dcs:50", &graph);
  OptimizerOptions options = Quiet();
  options.nonmonotonic_steps = true;
  const OptimizerSummary summary = Optimize(&graph, options, nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_EQ(summary.linear_solver, "SPARSE_NORMAL_CHOLESKY");
  // From dead reckoning (chi2 1.3e8) to a consistent map: the chi2 ends
  // below the number of factors (10608).
  EXPECT_GT(summary.initial_chi2, 1e8);
  EXPECT_LT(summary.final_chi2, 10608.0);
  // Loop closure through the landmarks: the odometry factors stay close to
  // their measurements (mean chi2 per odometry factor well below 10).
  double odometry_chi2 = 0.0;
  for (const auto& [id, f] : graph.factors()) {
    double chi2 = 0.0;
    if (f.type == FactorType::kBetweenSE2 && graph.FactorChi2(f, &chi2)) {
      odometry_chi2 += chi2;
    }
  }
  EXPECT_LT(odometry_chi2 / odometry, 10.0);
}

// The shipped Victoria Park config through the command line: converges and
// draws the map.
TEST(LandmarkDataTest, VictoriaParkConfigThroughTheCommandLine) {
  const std::string path = DatasetPath("isam_format/isam_victoriaPark.txt");
  SLAM_REQUIRE_DATASET(path);
  const std::string dir = ::slam::testing::TempDir();
  const std::string log = dir + "/log.txt";
  const int code = ::slam::testing::RunSlam(
      "optimize --config " + ::slam::testing::ConfigPath("victoria_park.yaml") +
          " -i " + path + " -o " + dir + "/vp.g2o --plot " + dir +
          "/plots --report " + dir + "/report.json --quiet",
      log);
  ASSERT_EQ(code, 0) << ::slam::testing::ReadText(log);
  EXPECT_TRUE(::slam::testing::Exists(dir + "/plots/map.png"));
  Graph back;
  std::string error;
  ASSERT_TRUE(ReadG2o(dir + "/vp.g2o", {}, &back, nullptr, &error)) << error;
  EXPECT_EQ(back.NumNodes(), 6969u + 151u);
  // The g2o file has no robust kernels: its plain chi2 is the optimum's.
  EXPECT_LT(back.Chi2(), 10608.0);
}

// The default command on Victoria Park (no config): one batch solve from
// dead reckoning stops in a local minimum (chi2 503277, landmarks up to
// 265 m off; landmark_stages: 1 shows it); solving growing halves of the
// trajectory first reaches the good minimum (6183.93; incremental iSAM's
// estimate scores 6188.29 in this objective).
TEST(LandmarkDataTest, VictoriaParkDefaultReachesTheGoodMinimum) {
  const std::string path = DatasetPath("isam_format/isam_victoriaPark.txt");
  SLAM_REQUIRE_DATASET(path);
  const std::string dir = ::slam::testing::TempDir();
  ::slam::testing::WriteText(dir + "/one.yaml",
                             "optimize:\n  landmark_stages: 1\n");
  double chi2[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    const std::string log = dir + "/log.txt";
    ASSERT_EQ(
        ::slam::testing::RunSlam(
            "optimize " +
                std::string(k == 0 ? "" : "--config " + dir + "/one.yaml ") +
                "-i " + path + " -o " + dir + "/vp.g2o --quiet",
            log),
        0)
        << ::slam::testing::ReadText(log);
    Graph back;
    std::string error;
    ASSERT_TRUE(ReadG2o(dir + "/vp.g2o", {}, &back, nullptr, &error)) << error;
    chi2[k] = back.Chi2();
  }
  EXPECT_NEAR(chi2[0], 6183.93, 0.01);
  EXPECT_GT(chi2[1], 1e5);
}

Graph ReadKitti(StereoVoReport* report) {
  Graph graph;
  std::string error;
  EXPECT_TRUE(ReadStereoVo(
      DatasetPath("stereo_vo_factors/gtsam_VO_stereo_factors_large.txt"),
      DatasetPath("stereo_vo_factors/gtsam_VO_calibration.txt"),
      DatasetPath("stereo_vo_factors/gtsam_VO_camera_poses_large.txt"), &graph,
      report, &error))
      << error;
  return graph;
}

TEST(LandmarkDataTest, KittiStereoBundleAdjustmentConverges) {
  SLAM_REQUIRE_DATASET(
      DatasetPath("stereo_vo_factors/gtsam_VO_stereo_factors_large.txt"));
  StereoVoReport report;
  Graph graph = ReadKitti(&report);
  EXPECT_EQ(report.poses, 26);
  EXPECT_EQ(report.measurements, 8189);
  EXPECT_GT(report.landmarks, 1000);
  const PixelErrorStats before = CameraPixelErrors(graph);
  EXPECT_EQ(before.factors, 8189);
  EXPECT_EQ(before.behind, 0);
  // The poses are camera-to-world: the file's points reproject to about a
  // pixel. (Read as world-to-camera they would be off by far more.)
  EXPECT_LT(before.rms, 3.0);
  const OptimizerSummary summary = Optimize(&graph, Quiet(), nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_EQ(summary.linear_solver, "SPARSE_SCHUR");
  const PixelErrorStats after = CameraPixelErrors(graph);
  EXPECT_LT(after.rms, 0.6 * before.rms);
  EXPECT_EQ(after.behind, 0);
  EXPECT_LT(summary.final_chi2, 0.2 * summary.initial_chi2);
}

TEST(LandmarkDataTest, KittiPosesReadAsWorldToCameraDoNotFit) {
  SLAM_REQUIRE_DATASET(
      DatasetPath("stereo_vo_factors/gtsam_VO_stereo_factors_large.txt"));
  StereoVoReport report;
  Graph graph = ReadKitti(&report);
  // Invert every camera pose (the other reading of the file): the points,
  // placed through the file's poses, no longer reproject.
  for (const auto& [key, node] : graph.nodes()) {
    if (key.kind != NodeKind::kPose3) continue;
    const Pose3 inverse = NodePose3(*node).Inverse();
    const std::vector<double> v = Pose3Value(inverse);
    std::copy(v.begin(), v.end(), node->value.begin());
  }
  const PixelErrorStats inverted = CameraPixelErrors(graph);
  EXPECT_GT(inverted.rms + 100.0 * inverted.behind, 20.0);
}

TEST(LandmarkDataTest, GtsamTrackXyzFilesFollowG2oOffsetSemantics) {
  const std::string identity =
      DatasetPath("landmarks_3d/gtsam_edge_se3_trackxyz_example.g2o");
  const std::string offset = DatasetPath(
      "landmarks_3d/gtsam_edge_se3_trackxyz_nonidentity_offset.g2o");
  SLAM_REQUIRE_DATASET(identity);
  SLAM_REQUIRE_DATASET(offset);
  std::string error;
  Graph a, b;
  ASSERT_TRUE(ReadPoseGraph(identity, {}, &a, nullptr, &error)) << error;
  ASSERT_TRUE(ReadPoseGraph(offset, {}, &b, nullptr, &error)) << error;
  for (const Graph* g : {&a, &b}) {
    ASSERT_EQ(g->NumNodes(), 2u);
    ASSERT_EQ(g->NumFactors(), 1u);
    EXPECT_EQ(g->FindNode(Point3Key(9))->value,
              (std::vector<double>{0, 0, 3.5}));
    EXPECT_TRUE(g->HasNode(Pose3Key(7)));
  }
  // Pose 7 at (1, -2, 0.5), yawed 90 deg: the point (0, 0, 3.5) is at
  // (2, 1, 3) in the body frame, the measurement: zero error.
  EXPECT_NEAR(a.Chi2(), 0.0, 1e-20);
  // With the sensor 0.1 m ahead along the body x axis the point is at
  // (1.9, 1, 3) in the sensor frame: e = (-0.1, 0, 0), chi2 = 0.01 I11.
  EXPECT_NEAR(b.Chi2(), 0.01 * 72.57142857142857, 1e-10);
  const Pose3 s = SensorOffsetOf(b.factors().begin()->second);
  EXPECT_EQ(s.t, Eigen::Vector3d(0.1, 0, 0));
}

TEST(LandmarkDataTest, GtsamLandmarkExamplesLoad) {
  const std::string vertices =
      DatasetPath("landmarks_3d/gtsam_example_with_vertices.g2o");
  const std::string known =
      DatasetPath("landmarks_3d/gtsam_known_landmark_localization_3.g2o");
  SLAM_REQUIRE_DATASET(vertices);
  SLAM_REQUIRE_DATASET(known);
  std::string error;
  Graph g;
  ASSERT_TRUE(ReadPoseGraph(vertices, {}, &g, nullptr, &error)) << error;
  EXPECT_EQ(g.NumNodes(), 16u);
  EXPECT_EQ(g.NumFactors(), 0u);
  EXPECT_EQ(g.FindNode(Point3Key(5))->value,
            (std::vector<double>{-10, 10, -10}));
  EXPECT_EQ(g.FindNode(Pose3Key(1))->value[0], 28.2843);
  Graph k;
  ASSERT_TRUE(ReadPoseGraph(known, {}, &k, nullptr, &error)) << error;
  int relative = 0, between = 0;
  for (const auto& [id, f] : k.factors()) {
    relative += f.type == FactorType::kRelativePoint3;
    between += f.type == FactorType::kBetweenSE3;
  }
  EXPECT_EQ(k.NumNodes(), 7u);
  EXPECT_EQ(relative, 12);
  EXPECT_EQ(between, 2);
  EXPECT_EQ(k.FindNode(Point3Key(2))->value, (std::vector<double>{2, -4, 3}));
  // The measurements were simulated from poses near the vertices: the
  // optimum is close to the file's values and the cost drops.
  const OptimizerSummary summary = Optimize(&k, Quiet(), nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_LE(summary.final_chi2, summary.initial_chi2);
}

TEST(LandmarkDataTest, ToroExampleWithBearingRangeOptimizes) {
  const std::string path = DatasetPath("posegraph_toro/gtsam_example.graph");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, nullptr, &error)) << error;
  const OptimizerSummary summary = Optimize(&graph, Quiet(), nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_LT(summary.final_chi2, summary.initial_chi2);
}

TEST(LandmarkDataTest, OptimizeCommandRunsStereoVo) {
  const std::string factors =
      DatasetPath("stereo_vo_factors/gtsam_VO_stereo_factors_large.txt");
  SLAM_REQUIRE_DATASET(factors);
  const std::string dir = ::slam::testing::TempDir();
  const std::string log = dir + "/log.txt";
  ASSERT_EQ(
      ::slam::testing::RunSlam(
          "optimize -i " + factors + " --stereo_calibration " +
              DatasetPath("stereo_vo_factors/gtsam_VO_calibration.txt") +
              " --stereo_poses " +
              DatasetPath("stereo_vo_factors/gtsam_VO_camera_poses_large.txt") +
              " --quiet -o " + dir + "/ba.g2o",
          log),
      0)
      << ::slam::testing::ReadText(log);
  const std::string text = ::slam::testing::ReadText(log);
  EXPECT_TRUE(::slam::testing::Contains(text, "reprojection RMS ")) << text;
  EXPECT_TRUE(::slam::testing::Contains(text, "SPARSE_SCHUR")) << text;
  Graph back;
  std::string error;
  ASSERT_TRUE(ReadG2o(dir + "/ba.g2o", {}, &back, nullptr, &error)) << error;
  EXPECT_EQ(back.NumFactors(), 8189u);
  // Missing the poses flag: usage error, nothing written.
  EXPECT_EQ(::slam::testing::RunSlam("optimize -i " + factors +
                                         " --stereo_calibration x -o " + dir +
                                         "/none.g2o",
                                     log),
            2);
  EXPECT_FALSE(::slam::testing::Exists(dir + "/none.g2o"));
}

// Victoria Park through the iSAM writer and the g2o writer, KITTI through
// the g2o writer: the same graph comes back (g2o bit for bit; iSAM to the
// rounding of its square-root information).
TEST(LandmarkDataTest, RealLandmarkGraphsRoundTrip) {
  const std::string path = DatasetPath("isam_format/isam_victoriaPark.txt");
  SLAM_REQUIRE_DATASET(path);
  const std::string dir = ::slam::testing::TempDir();
  Graph graph;
  std::string error;
  ASSERT_TRUE(ReadIsam(path, {}, &graph, nullptr, &error)) << error;
  ASSERT_TRUE(WriteIsam(dir + "/vp.txt", graph, &error)) << error;
  Graph isam;
  ASSERT_TRUE(ReadIsam(dir + "/vp.txt", {}, &isam, nullptr, &error)) << error;
  ASSERT_EQ(isam.NumFactors(), graph.NumFactors());
  auto it = isam.factors().begin();
  for (const auto& [id, f] : graph.factors()) {
    ASSERT_EQ(it->second.keys, f.keys);
    ASSERT_EQ(it->second.measurement, f.measurement);
    ASSERT_LT((it->second.information - f.information).norm(),
              1e-12 * f.information.norm());
    ++it;
  }
  StereoVoReport report;
  Graph kitti = ReadKitti(&report);
  for (Graph* g : {&graph, &kitti}) {
    ASSERT_TRUE(WriteG2o(dir + "/g.g2o", *g, &error)) << error;
    Graph back;
    ASSERT_TRUE(ReadG2o(dir + "/g.g2o", {}, &back, nullptr, &error)) << error;
    ASSERT_EQ(back.NumNodes(), g->NumNodes());
    ASSERT_EQ(back.NumFactors(), g->NumFactors());
    for (const auto& [key, node] : g->nodes()) {
      ASSERT_TRUE(back.HasNode(key)) << key.ToString();
      EXPECT_EQ(back.FindNode(key)->value, node->value) << key.ToString();
    }
    auto ib = back.factors().begin();
    for (const auto& [id, f] : g->factors()) {
      EXPECT_EQ(ib->second.type, f.type);
      EXPECT_EQ(ib->second.measurement, f.measurement);
      EXPECT_EQ(ib->second.information, f.information);
      ++ib;
    }
    EXPECT_EQ(back.Chi2(), g->Chi2());
  }
}

// iSAM's sphere400.txt (EDGE3 lines only): read as iSAM's square-root
// information (translation sqrt 10 -> information 100; TORO's reading took
// 10), 400 poses and 779 constraints as isam_data_README.txt says.
TEST(LandmarkDataTest, IsamSphere400IsReadWithSquareRootInformation) {
  const std::string path = DatasetPath("isam_format/isam_sphere400.txt");
  SLAM_REQUIRE_DATASET(path);
  Graph graph;
  GraphReadReport report;
  std::string error;
  ASSERT_TRUE(ReadPoseGraph(path, {}, &graph, &report, &error)) << error;
  EXPECT_EQ(graph.NumNodes(), 400u);
  EXPECT_EQ(graph.NumFactors(), 779u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(::slam::testing::Contains(report.warnings[0], "read as iSAM"));
  for (const auto& [id, f] : graph.factors()) {
    ASSERT_EQ(f.type, FactorType::kBetweenSE3);
    // Isotropic translation information: R_z^T (100 I) R_z = 100 I.
    const Eigen::Matrix3d info_t = f.information.topLeftCorner(3, 3);
    EXPECT_NEAR(info_t.trace(), 300.0, 1e-9);
  }
}

}  // namespace
}  // namespace slam
