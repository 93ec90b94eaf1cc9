// Known-answer end-to-end tests of the landmark and camera factors on the
// simulator's landmark worlds (datasets/simulator.h): for every world
// (range-bearing 2D, relative-position 2D, 3D relative position with a sensor
// offset, stereo bundle adjustment, monocular bundle adjustment with radtan
// distortion) the noisy graph is optimized and
//   - the ground truth's chi2 is consistent with chi2(R), R = residual
//     dimensions, and the optimum's with chi2(R - D), D = free dimensions,
//     and the optimum's chi2 is not above the truth's (the truth is a
//     feasible point: the gauge is fixed at true values);
//   - the RMS position error of the poses (ATE, no alignment: the gauge nodes
//     are fixed at their true values) and of the landmarks is within the
//     noise: below 3x (and above 1/5 of) the RMS predicted by the marginal
//     covariances at the optimum, i.e. the noise sigmas propagated through
//     the problem's geometry; and far below the initial error.
// Monocular BA has a 7-dof gauge (rotation, translation, scale): the world
// without odometry fixes poses 0 and 1 at their true values, which removes
// it, so no Sim(3) alignment is needed.
// Also: determinism, structure, config validation, and the CLI chain
// simulate -> optimize --gt -> eval.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/graph.h"
#include "core/marginals.h"
#include "core/optimizer.h"
#include "datasets/g2o_io.h"
#include "datasets/simulator.h"
#include "factors/landmark_factors.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::ReadText;
using ::slam::testing::RunSlam;
using ::slam::testing::TempDir;

bool IsPoint(const Key& key) {
  return key.kind == NodeKind::kPoint2 || key.kind == NodeKind::kPoint3;
}

SimulationConfig Landmarks2d(const std::string& observations) {
  SimulationConfig c;
  c.seed = 11;
  c.world.type = "landmarks2d";
  c.world.num_poses = 200;
  c.world.grid_size = 8;
  c.landmarks.num_landmarks = 120;
  c.landmarks.max_range = 4.0;
  c.landmarks.observations = observations;
  if (observations == "relative_position") {
    c.landmarks.field_of_view = M_PI;  // Looks ahead only.
  }
  return c;
}

SimulationConfig Landmarks3d() {
  SimulationConfig c;
  c.seed = 12;
  c.world.type = "landmarks3d";
  c.world.num_poses = 150;
  c.world.grid_size = 5;
  c.landmarks.num_landmarks = 150;
  c.landmarks.margin = 1.0;
  c.landmarks.max_range = 3.0;
  // Sensor 0.2 m ahead, 0.1 m left, 0.3 m up, yawed by 30 degrees and
  // pitched: a rotation about (0, 0.6, 0.8).
  const double s = std::sin(M_PI / 12.0), w = std::cos(M_PI / 12.0);
  c.landmarks.sensor_offset = {0.2, 0.1, 0.3, 0.0, 0.6 * s, 0.8 * s, w};
  return c;
}

SimulationConfig Camera(const std::string& world) {
  SimulationConfig c;
  c.seed = 13;
  c.world.type = world;
  c.world.num_poses = 40;
  c.world.radius = 10.0;
  c.landmarks.num_landmarks = 120;
  c.landmarks.field_radius = 5.0;
  c.landmarks.odometry = false;  // Pure bundle adjustment.
  if (world == "monocular") {
    c.camera.k1 = -0.2;
    c.camera.k2 = 0.05;
    c.camera.p1 = 0.001;
    c.camera.p2 = -0.0005;
  }
  return c;
}

void SimulateOrDie(const SimulationConfig& config, SimulationResult* result) {
  std::string error;
  ASSERT_TRUE(Simulate(config, result, &error)) << error;
}

Eigen::Vector3d Position(const std::vector<double>& v, const Key& key) {
  const bool two_d =
      key.kind == NodeKind::kPose2 || key.kind == NodeKind::kPoint2;
  return Eigen::Vector3d(v[0], v[1], two_d ? 0.0 : v[2]);
}

// RMS distance between the node positions (poses or points) and the truth.
double RmsError(const Graph& graph, const SimulationResult& r, bool points) {
  double sum = 0.0;
  int count = 0;
  for (const auto& [key, node] : graph.nodes()) {
    if (IsPoint(key) != points) continue;
    sum += (Position(node->value, key) - Position(r.ground_truth.at(key), key))
               .squaredNorm();
    ++count;
  }
  return std::sqrt(sum / count);
}

// The RMS position error predicted by the marginal covariances: sqrt of the
// mean trace of the position block (translation first for poses; the trace
// does not depend on the frame).
double PredictedRms(Graph* graph, bool points) {
  std::vector<Key> keys;
  for (const auto& [key, node] : graph->nodes()) {
    if (IsPoint(key) == points) keys.push_back(key);
  }
  std::map<Key, Eigen::MatrixXd> covariances;
  std::string error;
  if (!ComputeMarginals(graph, keys, &covariances, &error)) {
    ADD_FAILURE() << error;
    return NAN;
  }
  double sum = 0.0;
  for (const Key& key : keys) {
    const int dims =
        (key.kind == NodeKind::kPose2 || key.kind == NodeKind::kPoint2) ? 2 : 3;
    sum += covariances[key].topLeftCorner(dims, dims).trace();
  }
  return std::sqrt(sum / keys.size());
}

std::map<Key, std::vector<double>> Values(const Graph& graph) {
  std::map<Key, std::vector<double>> values;
  for (const auto& [key, node] : graph.nodes()) values[key] = node->value;
  return values;
}

// |chi2 - dof| within 5 standard deviations of chi2(dof).
void ExpectChi2Consistent(double chi2, double dof, const char* what) {
  EXPECT_NEAR(chi2, dof, 5.0 * std::sqrt(2.0 * dof))
      << what << ": chi2 " << chi2 << " vs " << dof << " degrees of freedom";
}

struct KnownAnswer {
  double initial_ate = 0.0, final_ate = 0.0, predicted_ate = 0.0;
  double initial_landmarks = 0.0, final_landmarks = 0.0;
  double predicted_landmarks = 0.0;
};

// Simulate, optimize and check the result against the truth and the noise.
KnownAnswer RunKnownAnswer(const SimulationConfig& config) {
  KnownAnswer k;
  SimulationResult r;
  SimulateOrDie(config, &r);
  EXPECT_GT(r.landmarks.size(), 20u);
  EXPECT_GT(r.landmark_factors.size(), 5 * r.landmarks.size());
  Graph& graph = r.graph;
  k.initial_ate = RmsError(graph, r, false);
  k.initial_landmarks = RmsError(graph, r, true);

  // The truth: chi2(R).
  const std::map<Key, std::vector<double>> initial = Values(graph);
  SetNodeValues(r.ground_truth, &graph);
  const double truth_chi2 = graph.Chi2();
  ExpectChi2Consistent(truth_chi2, r.residual_dimensions, "ground truth");
  SetNodeValues(initial, &graph);

  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary summary = Optimize(&graph, options, nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_LT(summary.final_chi2, summary.initial_chi2);
  ExpectChi2Consistent(summary.final_chi2,
                       r.residual_dimensions - r.free_dimensions, "optimum");
  EXPECT_LE(summary.final_chi2, truth_chi2 * (1.0 + 1e-9));

  k.final_ate = RmsError(graph, r, false);
  k.final_landmarks = RmsError(graph, r, true);
  k.predicted_ate = PredictedRms(&graph, false);
  k.predicted_landmarks = PredictedRms(&graph, true);
  EXPECT_LT(k.final_ate, 3.0 * k.predicted_ate);
  EXPECT_GT(k.final_ate, 0.2 * k.predicted_ate);
  EXPECT_LT(k.final_landmarks, 3.0 * k.predicted_landmarks);
  EXPECT_GT(k.final_landmarks, 0.2 * k.predicted_landmarks);
  EXPECT_LT(k.final_ate, 0.25 * k.initial_ate);
  EXPECT_LT(k.final_landmarks, 0.25 * k.initial_landmarks);
  std::printf(
      "%s: %zu poses, %zu landmarks, %zu observations; %s, %d iterations; "
      "ATE %.4g -> %.4g m (predicted %.4g); landmark RMS %.4g -> %.4g m "
      "(predicted %.4g); chi2 %.6g (truth %.6g, dof %d)\n",
      config.world.type.c_str(), graph.NumNodes() - r.landmarks.size(),
      r.landmarks.size(), r.landmark_factors.size(),
      summary.linear_solver.c_str(), summary.iterations, k.initial_ate,
      k.final_ate, k.predicted_ate, k.initial_landmarks, k.final_landmarks,
      k.predicted_landmarks, summary.final_chi2, truth_chi2,
      r.residual_dimensions - r.free_dimensions);
  return k;
}

// ---------------------------------------------------------------------------

TEST(LandmarkSimulationTest, RangeBearing2dKnownAnswer) {
  const KnownAnswer k = RunKnownAnswer(Landmarks2d("range_bearing"));
  // A sanity bound in sigmas besides the marginals: a few range sigmas.
  EXPECT_LT(k.final_landmarks, 3.0 * 0.05 * 2.0);
}

TEST(LandmarkSimulationTest, RelativePosition2dKnownAnswer) {
  RunKnownAnswer(Landmarks2d("relative_position"));
}

TEST(LandmarkSimulationTest, BothObservations2dKnownAnswer) {
  RunKnownAnswer(Landmarks2d("both"));
}

TEST(LandmarkSimulationTest, RelativePoint3dWithSensorOffsetKnownAnswer) {
  RunKnownAnswer(Landmarks3d());
}

TEST(LandmarkSimulationTest, StereoBundleAdjustmentKnownAnswer) {
  RunKnownAnswer(Camera("stereo"));
}

TEST(LandmarkSimulationTest, MonocularBundleAdjustmentWithDistortion) {
  RunKnownAnswer(Camera("monocular"));
}

TEST(LandmarkSimulationTest, StereoWithOdometryKnownAnswer) {
  SimulationConfig config = Camera("stereo");
  config.landmarks.odometry = true;
  config.seed = 21;
  RunKnownAnswer(config);
}

// The sensor offset matters: the same observations read as if the sensor
// sat at the body origin make the truth far from consistent, so the offset
// is really applied by simulator and factor alike (and is not the identity
// by accident).
TEST(LandmarkSimulationTest, SensorOffsetIsApplied) {
  SimulationResult r;
  SimulateOrDie(Landmarks3d(), &r);
  SetNodeValues(r.ground_truth, &r.graph);
  double with_offset = 0.0, without_offset = 0.0;
  for (FactorId id : r.landmark_factors) {
    const Factor* f = r.graph.FindFactor(id);
    ASSERT_EQ(f->type, FactorType::kRelativePoint3);
    const Pose3 offset = SensorOffsetOf(*f);
    EXPECT_NEAR(offset.t.x(), 0.2, 1e-15);
    Factor plain;
    std::string error;
    ASSERT_TRUE(MakeRelativePoint3(f->keys[0], f->keys[1],
                                   f->measurement.head<3>(), Pose3(),
                                   f->information, &plain, &error))
        << error;
    double chi2 = 0.0;
    ASSERT_TRUE(r.graph.FactorChi2(*f, &chi2));
    with_offset += chi2;
    ASSERT_TRUE(r.graph.FactorChi2(plain, &chi2));
    without_offset += chi2;
  }
  const double dof = 3.0 * r.landmark_factors.size();
  ExpectChi2Consistent(with_offset, dof, "with the offset");
  EXPECT_GT(without_offset, 100.0 * dof);
}

TEST(LandmarkSimulationTest, DeterministicAndSeeded) {
  for (const SimulationConfig& config :
       {Landmarks2d("both"), Landmarks3d(), Camera("stereo"),
        Camera("monocular")}) {
    SCOPED_TRACE(config.world.type);
    SimulationResult a, b, c;
    SimulateOrDie(config, &a);
    SimulateOrDie(config, &b);
    SimulationConfig other = config;
    other.seed += 100;
    SimulateOrDie(other, &c);
    EXPECT_EQ(Values(a.graph), Values(b.graph));
    EXPECT_EQ(a.ground_truth, b.ground_truth);
    EXPECT_EQ(a.landmarks, b.landmarks);
    ASSERT_EQ(a.graph.NumFactors(), b.graph.NumFactors());
    auto fb = b.graph.factors().begin();
    for (const auto& [id, factor] : a.graph.factors()) {
      EXPECT_EQ(factor.type, fb->second.type);
      EXPECT_EQ(factor.keys, fb->second.keys);
      EXPECT_EQ(factor.measurement, fb->second.measurement);
      EXPECT_EQ(factor.information, fb->second.information);
      ++fb;
    }
    EXPECT_NE(Values(a.graph), Values(c.graph));
  }
}

TEST(LandmarkSimulationTest, Structure) {
  for (const SimulationConfig& config :
       {Landmarks2d("range_bearing"), Landmarks2d("both"), Landmarks3d(),
        Camera("stereo"), Camera("monocular")}) {
    SCOPED_TRACE(config.world.type + " " + config.landmarks.observations);
    SimulationResult r;
    SimulateOrDie(config, &r);
    const int n = config.world.num_poses;
    const bool camera =
        config.world.type == "stereo" || config.world.type == "monocular";
    ASSERT_EQ(r.graph.NumNodes(), n + r.landmarks.size());
    EXPECT_EQ(r.odometry_factors.size(),
              config.landmarks.odometry ? static_cast<size_t>(n - 1) : 0u);
    EXPECT_EQ(r.graph.NumFactors(),
              r.odometry_factors.size() + r.landmark_factors.size());
    EXPECT_TRUE(r.loop_closure_factors.empty());
    EXPECT_EQ(r.ground_truth.size(), r.graph.NumNodes());
    EXPECT_EQ(r.ground_truth_trajectory.size(), static_cast<size_t>(n));
    // Landmark ids follow the pose ids (no id is used twice), in order.
    for (size_t j = 0; j < r.landmarks.size(); ++j) {
      EXPECT_EQ(r.landmarks[j].id, n + static_cast<int64_t>(j));
      EXPECT_EQ(r.landmarks[j].kind,
                r.is_3d ? NodeKind::kPoint3 : NodeKind::kPoint2);
    }
    // Fixed: pose 0, and pose 1 for monocular BA without odometry; at the
    // truth.
    int fixed = 0;
    for (const auto& [key, node] : r.graph.nodes()) {
      if (!node->fixed) continue;
      ++fixed;
      EXPECT_EQ(node->value, r.ground_truth.at(key)) << key.ToString();
      EXPECT_FALSE(IsPoint(key));
    }
    const bool mono_ba =
        config.world.type == "monocular" && !config.landmarks.odometry;
    EXPECT_EQ(fixed, mono_ba ? 2 : 1);
    // Every landmark observed at least min_observations times; observations
    // in pose order.
    std::map<Key, int> count;
    int64_t last_pose = -1;
    for (FactorId id : r.landmark_factors) {
      const Factor* f = r.graph.FindFactor(id);
      ASSERT_EQ(f->keys.size(), 2u);
      EXPECT_GE(f->keys[0].id, last_pose);
      last_pose = f->keys[0].id;
      ++count[f->keys[1]];
    }
    EXPECT_EQ(count.size(), r.landmarks.size());
    for (const auto& [key, c] : count) {
      EXPECT_GE(c, std::max(config.landmarks.min_observations, camera ? 2 : 1));
    }
    // Every factor is defined at the initial values (no point behind a
    // camera that sees it).
    for (const auto& [id, f] : r.graph.factors()) {
      double chi2 = 0.0;
      EXPECT_TRUE(r.graph.FactorChi2(f, &chi2) && std::isfinite(chi2)) << id;
    }
    // Dimensions: residuals of all factors, tangent sizes of the free nodes.
    int residuals = 0;
    for (const auto& [id, f] : r.graph.factors()) {
      residuals += f.cost->num_residuals();
    }
    EXPECT_EQ(r.residual_dimensions, residuals);
    const int pose_dim = r.is_3d ? 6 : 3;
    EXPECT_EQ(r.free_dimensions,
              pose_dim * (n - fixed) +
                  (r.is_3d ? 3 : 2) * static_cast<int>(r.landmarks.size()));
  }
}

// Some landmarks of `config` were placed again (their first initial value
// lay behind a camera); every factor is defined at the initial values and the
// solve converges close to the truth.
void ExpectPlacedAgainAndSolved(const SimulationConfig& config) {
  SimulationResult r;
  SimulateOrDie(config, &r);
  EXPECT_GT(r.reinitialized_landmarks, 0);
  EXPECT_TRUE(std::isfinite(r.graph.Chi2()));
  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary summary = Optimize(&r.graph, options, nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_LT(RmsError(r.graph, r, true), 0.1);
}

// Monocular: with drift, the widest pair of rays can put a point behind a
// camera; those points are triangulated again from an early pair, so that
// every reprojection error is defined and the solve can start.
TEST(LandmarkSimulationTest, MonocularPointsBehindCamerasArePlacedAgain) {
  SimulationConfig config = Camera("monocular");
  config.world.num_poses = 60;
  config.landmarks.num_landmarks = 200;
  config.seed = 3;
  ExpectPlacedAgainAndSolved(config);
}

// Stereo: far points (small disparity, 1 px noise) triangulated from the
// first observation can land behind the cameras across the circle; they are
// placed again from the observation with the largest disparity.
TEST(LandmarkSimulationTest, StereoPointsBehindCamerasArePlacedAgain) {
  SimulationConfig config = Camera("stereo");
  config.world.radius = 20.0;
  config.world.num_poses = 30;
  config.landmarks.num_landmarks = 80;
  config.landmarks.odometry = true;
  config.seed = 1;
  ExpectPlacedAgainAndSolved(config);
}

// Camera worlds: the true points lie in the ball, in front of every camera
// that observes them, and the cameras look at the origin.
TEST(LandmarkSimulationTest, CameraGeometry) {
  SimulationConfig config = Camera("stereo");
  SimulationResult r;
  SimulateOrDie(config, &r);
  for (const StampedPose& p : r.ground_truth_trajectory) {
    EXPECT_NEAR(p.pose.t.norm(), config.world.radius, 1e-9);
    EXPECT_NEAR(p.pose.t.z(), 0.0, 1e-12);
    const Eigen::Vector3d forward = p.pose.q * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d down = p.pose.q * Eigen::Vector3d::UnitY();
    EXPECT_NEAR((forward + p.pose.t.normalized()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((down - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-9);
  }
  for (const Key& key : r.landmarks) {
    const std::vector<double>& v = r.ground_truth.at(key);
    EXPECT_LE(Eigen::Vector3d(v[0], v[1], v[2]).norm(),
              config.landmarks.field_radius + 1e-12);
  }
  for (FactorId id : r.landmark_factors) {
    const Factor* f = r.graph.FindFactor(id);
    const std::vector<double>& c = r.ground_truth.at(f->keys[0]);
    const std::vector<double>& v = r.ground_truth.at(f->keys[1]);
    const Pose3 camera(Eigen::Vector3d(c[0], c[1], c[2]),
                       Eigen::Quaterniond(c[6], c[3], c[4], c[5]));
    const Eigen::Vector3d local =
        camera.Inverse() * Eigen::Vector3d(v[0], v[1], v[2]);
    EXPECT_GE(local.z(), config.camera.min_depth);
  }
}

// ---------------------------------------------------------------------------
// Through the binary: simulate -> optimize --gt -> eval, and the landmarks
// of the optimized file against landmarks.txt.

std::map<int64_t, Eigen::Vector3d> ReadLandmarkTruth(const std::string& path) {
  std::map<int64_t, Eigen::Vector3d> points;
  std::istringstream in(ReadText(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    int64_t id;
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    fields >> id >> p.x() >> p.y();
    if (!(fields >> p.z())) p.z() = 0.0;
    points[id] = p;
  }
  return points;
}

double LandmarkRms(const Graph& graph,
                   const std::map<int64_t, Eigen::Vector3d>& truth) {
  double sum = 0.0;
  int count = 0;
  for (const auto& [key, node] : graph.nodes()) {
    if (!IsPoint(key)) continue;
    sum += (Position(node->value, key) - truth.at(key.id)).squaredNorm();
    ++count;
  }
  EXPECT_EQ(count, static_cast<int>(truth.size()));
  return std::sqrt(sum / count);
}

// The ATE RMSE of `slam optimize --gt`/`slam eval` output: the first number
// of the "APE translation [m]" row.
double ParseApeRmse(const std::string& log) {
  const std::string row = "APE translation [m]";
  const size_t at = log.find(row);
  if (at == std::string::npos) return -1.0;
  std::istringstream in(log.substr(at + row.size()));
  double value = -1.0;
  in >> value;
  return value;
}

void RunCliChain(const std::string& world, const std::string& extra) {
  SCOPED_TRACE(world);
  const std::string tmp = TempDir();
  const std::string dir = tmp + "/" + world;
  const std::string log = tmp + "/log";
  ASSERT_EQ(RunSlam("simulate -o " + dir + " --world " + world + extra, log), 0)
      << ReadText(log);
  ASSERT_TRUE(testing::Exists(dir + "/landmarks.txt")) << ReadText(log);
  const std::map<int64_t, Eigen::Vector3d> truth =
      ReadLandmarkTruth(dir + "/landmarks.txt");
  ASSERT_GT(truth.size(), 20u);

  Graph noisy;
  std::string error;
  ASSERT_TRUE(
      ReadG2o(dir + "/graph.g2o", GraphReadOptions(), &noisy, nullptr, &error))
      << error;
  const double initial_rms = LandmarkRms(noisy, truth);

  const std::string optimized = dir + "/optimized.g2o";
  ASSERT_EQ(RunSlam("optimize -i " + dir + "/graph.g2o -o " + optimized +
                        " --gt " + dir + "/ground_truth.tum",
                    log),
            0)
      << ReadText(log);
  const std::string optimize_log = ReadText(log);
  const double optimize_ate = ParseApeRmse(optimize_log);
  EXPECT_GE(optimize_ate, 0.0) << optimize_log;

  Graph result;
  ASSERT_TRUE(ReadG2o(optimized, GraphReadOptions(), &result, nullptr, &error))
      << error;
  const double final_rms = LandmarkRms(result, truth);
  EXPECT_LT(final_rms, 0.25 * initial_rms);

  ASSERT_EQ(
      RunSlam("eval --ref " + dir + "/ground_truth.tum --est " + optimized,
              log),
      0)
      << ReadText(log);
  const double eval_ate = ParseApeRmse(ReadText(log));
  EXPECT_NEAR(eval_ate, optimize_ate, 1e-6 + 1e-3 * optimize_ate)
      << ReadText(log);
  std::printf("%s CLI: landmark RMS %.4g -> %.4g m, ATE %.4g m\n",
              world.c_str(), initial_rms, final_rms, eval_ate);
}

TEST(LandmarkSimulationCliTest, SimulateOptimizeEvalLandmarks2d) {
  RunCliChain("landmarks2d", " --num_poses 150 --num_landmarks 100");
}

TEST(LandmarkSimulationCliTest, SimulateOptimizeEvalStereo) {
  RunCliChain("stereo", " --num_poses 30 --num_landmarks 80");
}

TEST(LandmarkSimulationCliTest, SimulateOptimizeEvalLandmarks3d) {
  RunCliChain("landmarks3d", " --num_poses 120 --num_landmarks 150");
}

TEST(LandmarkSimulationCliTest, SimulateOptimizeEvalMonocular) {
  RunCliChain("monocular", " --num_poses 30 --num_landmarks 80");
}

// Pure bundle adjustment from the shipped configs: no odometry factors, the
// fixed poses (two for monocular) travel through the g2o FIX line.
TEST(LandmarkSimulationCliTest, ShippedBundleAdjustmentConfigs) {
  const std::string configs =
      std::string(SLAM_TEST_DATA_DIR) + "/../../configs";
  RunCliChain("stereo", " --config " + configs +
                            "/simulate_stereo.yaml --num_poses 30"
                            " --num_landmarks 80");
  RunCliChain("monocular", " --config " + configs +
                               "/simulate_monocular.yaml --num_poses 30"
                               " --num_landmarks 80");
}

// Landmark SLAM from dead reckoning (no landmark values in the file, as
// Victoria Park): 3000 poses with 0.06 rad odometry rotation noise,
// landmarks seen within 2 m. One batch solve from the odometry chain and
// first-sighting landmarks stops in a local minimum (chi2 13306); the
// default staged solve (optimize.landmark_stages) reaches the minimum found
// from the ground truth (6869.01).
TEST(LandmarkSimulationTest, DeadReckoningStartReachesTheOptimumInStages) {
  const std::string dir = testing::TempDir();
  const std::string log = dir + "/log.txt";
  testing::WriteText(dir + "/sim.yaml",
                     "simulate:\n"
                     "  seed: 2\n"
                     "  world: {type: landmarks2d, num_poses: 3000, step: 1.0,"
                     " grid_size: 30, turn_probability: 0.3}\n"
                     "  odometry: {sigma_translation: 0.05, "
                     "sigma_rotation: 0.06}\n"
                     "  landmarks: {num_landmarks: 100, margin: 2.0, "
                     "min_observations: 2, observations: relative_position,"
                     " max_range: 2.0, sigma_position: 0.05}\n");
  ASSERT_EQ(RunSlam("simulate --config " + dir + "/sim.yaml -o " + dir, log), 0)
      << ReadText(log);
  // The measurements alone, and the measurements from the ground truth.
  std::string edges, truth_start;
  {
    std::istringstream graph(ReadText(dir + "/graph.g2o"));
    std::istringstream truth(ReadText(dir + "/ground_truth.g2o"));
    std::string line;
    while (std::getline(truth, line)) {
      if (line.rfind("VERTEX", 0) == 0) truth_start += line + "\n";
    }
    while (std::getline(graph, line)) {
      if (line.rfind("EDGE", 0) == 0) edges += line + "\n";
    }
  }
  testing::WriteText(dir + "/edges.g2o", edges);
  testing::WriteText(dir + "/truth_start.g2o", truth_start + edges);
  testing::WriteText(dir + "/one.yaml", "optimize:\n  landmark_stages: 1\n");
  auto optimized_chi2 = [&](const std::string& args) {
    EXPECT_EQ(
        RunSlam("optimize " + args + " -o " + dir + "/out.g2o --quiet", log), 0)
        << ReadText(log);
    Graph out;
    std::string error;
    EXPECT_TRUE(ReadG2o(dir + "/out.g2o", {}, &out, nullptr, &error)) << error;
    return out.Chi2();
  };
  const double optimum =
      optimized_chi2("-i " + dir + "/truth_start.g2o --init none");
  const double staged = optimized_chi2("-i " + dir + "/edges.g2o");
  const double one_batch =
      optimized_chi2("-i " + dir + "/edges.g2o --config " + dir + "/one.yaml");
  EXPECT_NEAR(staged, optimum, 1e-6 * optimum);
  EXPECT_GT(one_batch, 1.5 * optimum);
}

}  // namespace
}  // namespace slam
