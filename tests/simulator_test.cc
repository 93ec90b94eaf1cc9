// Tests of the dataset simulator (datasets/simulator.h): determinism, the
// geometry of each world, the measurement statistics (the chi2 of the ground
// truth is chi2-distributed), and simulate -> optimize recovering the truth,
// with and without outlier loop closures.
#include "datasets/simulator.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/initialization.h"
#include "core/optimizer.h"
#include "factors/robust_kernels.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

SimulationConfig Config(const std::string& world, int num_poses,
                        uint64_t seed) {
  SimulationConfig config;
  config.world.type = world;
  config.world.num_poses = num_poses;
  config.seed = seed;
  if (world == "grid3d") config.world.grid_size = 5;
  return config;
}

void SimulateOrDie(const SimulationConfig& config, SimulationResult* result) {
  std::string error;
  ASSERT_TRUE(Simulate(config, result, &error)) << error;
}

Pose2 TruePose2(const SimulationResult& r, int k) {
  const std::vector<double>& v = r.ground_truth.at(Pose2Key(k));
  return Pose2(v[0], v[1], v[2]);
}

Pose3 TruePose3(const SimulationResult& r, int k) {
  const std::vector<double>& v = r.ground_truth.at(Pose3Key(k));
  return Pose3(Eigen::Vector3d(v[0], v[1], v[2]),
               Eigen::Quaterniond(v[6], v[3], v[4], v[5]));
}

Eigen::Vector3d Position(const std::vector<double>& value, bool is_3d) {
  return Eigen::Vector3d(value[0], value[1], is_3d ? value[2] : 0.0);
}

// RMS distance between the positions of the graph's nodes and `reference`.
double PositionRmse(const Graph& graph,
                    const std::map<Key, std::vector<double>>& reference,
                    bool is_3d) {
  double sum = 0.0;
  for (const auto& [key, node] : graph.nodes()) {
    sum += (Position(node->value, is_3d) - Position(reference.at(key), is_3d))
               .squaredNorm();
  }
  return std::sqrt(sum / graph.NumNodes());
}

std::map<Key, std::vector<double>> Values(const Graph& graph) {
  std::map<Key, std::vector<double>> values;
  for (const auto& [key, node] : graph.nodes()) values[key] = node->value;
  return values;
}

// Whitened residual of a factor at the graph's current values.
Eigen::VectorXd Residual(const Graph& graph, const Factor& factor) {
  const std::vector<const double*> blocks = graph.ParameterBlocks(factor);
  Eigen::VectorXd r(factor.cost->num_residuals());
  EXPECT_TRUE(factor.cost->Evaluate(blocks.data(), r.data(), nullptr));
  return r;
}

OptimizerSummary Solve(Graph* graph, InitMethod init) {
  std::string error;
  EXPECT_TRUE(InitializePoses(graph, init, &error)) << error;
  OptimizerOptions options;
  options.verbose = false;
  return Optimize(graph, options, nullptr);
}

void SetLoss(const SimulationResult& result, const std::vector<FactorId>& ids,
             const std::shared_ptr<ceres::LossFunction>& loss) {
  // The graph hands out factors read-only; the loss is not part of the
  // structure Ceres sees until BuildProblem, so setting it here is safe.
  for (FactorId id : ids) {
    const_cast<Factor*>(result.graph.FindFactor(id))->loss = loss;
  }
}

// ---------------------------------------------------------------------------

TEST(SimulatorTest, SameSeedSameDatasetOtherSeedOtherDataset) {
  for (const std::string world : {"grid2d", "grid3d", "sphere3d"}) {
    SCOPED_TRACE(world);
    SimulationConfig config = Config(world, 300, 7);
    config.loop_closures.outlier_fraction = 0.1;
    SimulationResult a, b, c;
    SimulateOrDie(config, &a);
    SimulateOrDie(config, &b);
    config.seed = 8;
    SimulateOrDie(config, &c);
    ASSERT_EQ(a.graph.NumNodes(), b.graph.NumNodes());
    ASSERT_EQ(a.graph.NumFactors(), b.graph.NumFactors());
    for (const auto& [key, node] : a.graph.nodes()) {
      EXPECT_EQ(node->value, b.graph.FindNode(key)->value);
    }
    auto fb = b.graph.factors().begin();
    for (const auto& [id, factor] : a.graph.factors()) {
      EXPECT_EQ(id, fb->first);
      EXPECT_EQ(factor.keys, fb->second.keys);
      EXPECT_EQ(factor.measurement, fb->second.measurement);
      EXPECT_EQ(factor.information, fb->second.information);
      ++fb;
    }
    EXPECT_EQ(a.outlier_factors, b.outlier_factors);
    EXPECT_EQ(a.ground_truth, b.ground_truth);
    // Another seed: other noise (the odometry measurements differ).
    const Factor& fa = a.graph.factors().begin()->second;
    const Factor& fc = c.graph.factors().begin()->second;
    EXPECT_NE(fa.measurement, fc.measurement);
    EXPECT_NE(a.graph.FindNode(a.graph.nodes().rbegin()->first)->value,
              c.graph.FindNode(c.graph.nodes().rbegin()->first)->value);
  }
}

TEST(SimulatorTest, RejectsInvalidConfigs) {
  struct Case {
    const char* setting;
    void (*change)(SimulationConfig*);
  };
  const Case cases[] = {
      {"world.type", [](SimulationConfig* c) { c->world.type = "torus"; }},
      {"world.num_poses", [](SimulationConfig* c) { c->world.num_poses = 1; }},
      {"world.step", [](SimulationConfig* c) { c->world.step = 0.0; }},
      {"world.grid_size", [](SimulationConfig* c) { c->world.grid_size = 1; }},
      {"world.turn_probability",
       [](SimulationConfig* c) { c->world.turn_probability = 1.5; }},
      {"world.poses_per_ring",
       [](SimulationConfig* c) { c->world.poses_per_ring = 2; }},
      {"odometry.sigma_translation",
       [](SimulationConfig* c) { c->odometry.sigma_translation = -1.0; }},
      {"odometry.sigma_rotation",
       [](SimulationConfig* c) { c->odometry.sigma_rotation = NAN; }},
      {"loop_closures.sigma_rotation",
       [](SimulationConfig* c) { c->loop_closures.noise.sigma_rotation = 0; }},
      {"loop_closures.probability",
       [](SimulationConfig* c) { c->loop_closures.probability = -0.1; }},
      {"loop_closures.min_index_gap",
       [](SimulationConfig* c) { c->loop_closures.min_index_gap = 1; }},
      {"loop_closures.outlier_fraction",
       [](SimulationConfig* c) { c->loop_closures.outlier_fraction = 1.0; }},
      // Landmark and camera settings (checked for every world type).
      {"landmarks.num_landmarks",
       [](SimulationConfig* c) { c->landmarks.num_landmarks = 0; }},
      {"landmarks.observations",
       [](SimulationConfig* c) { c->landmarks.observations = "sonar"; }},
      {"landmarks.max_range",
       [](SimulationConfig* c) { c->landmarks.max_range = -1; }},
      {"landmarks.field_of_view",
       [](SimulationConfig* c) { c->landmarks.field_of_view = 7.0; }},
      {"landmarks.sigma_bearing",
       [](SimulationConfig* c) { c->landmarks.sigma_bearing = NAN; }},
      {"landmarks.sigma_pixel",
       [](SimulationConfig* c) { c->landmarks.sigma_pixel = 0.0; }},
      {"landmarks.min_observations",
       [](SimulationConfig* c) { c->landmarks.min_observations = 0; }},
      {"landmarks.sensor_offset",
       [](SimulationConfig* c) {
         c->landmarks.sensor_offset = {1, 2};
       }},
      {"landmarks.sensor_offset",
       [](SimulationConfig* c) {
         c->landmarks.sensor_offset = {0, 0, 0, 0, 0, 0, 0.5};
       }},
      {"camera.fx", [](SimulationConfig* c) { c->camera.fx = 0.0; }},
      {"camera.baseline",
       [](SimulationConfig* c) { c->camera.baseline = -0.1; }},
      {"camera.k1", [](SimulationConfig* c) { c->camera.k1 = INFINITY; }},
      {"camera.width", [](SimulationConfig* c) { c->camera.width = 0; }},
      {"camera.max_depth",
       [](SimulationConfig* c) { c->camera.max_depth = 0.2; }},
      {"world.num_poses",  // Monocular BA fixes two poses.
       [](SimulationConfig* c) {
         c->world.type = "monocular";
         c->landmarks.odometry = false;
         c->world.num_poses = 2;
       }},
  };
  for (const Case& test_case : cases) {
    SimulationConfig config;
    test_case.change(&config);
    SimulationResult result;
    std::string error;
    EXPECT_FALSE(Simulate(config, &result, &error)) << test_case.setting;
    EXPECT_NE(error.find(test_case.setting), std::string::npos)
        << "error '" << error << "' does not name " << test_case.setting;
  }
  std::string error;
  EXPECT_TRUE(ValidateSimulationConfig(SimulationConfig(), &error)) << error;
}

TEST(SimulatorTest, Grid2dStructure) {
  SimulationConfig config = Config("grid2d", 400, 3);
  SimulationResult r;
  SimulateOrDie(config, &r);
  const int n = config.world.num_poses;
  EXPECT_FALSE(r.is_3d);
  ASSERT_EQ(r.graph.NumNodes(), static_cast<size_t>(n));
  ASSERT_EQ(r.odometry_factors.size(), static_cast<size_t>(n - 1));
  EXPECT_GT(r.loop_closure_factors.size(), 100u);
  EXPECT_TRUE(r.outlier_factors.empty());
  EXPECT_EQ(r.graph.NumFactors(),
            r.odometry_factors.size() + r.loop_closure_factors.size());

  // Node 0: identity, fixed; the only fixed node.
  const Node* first = r.graph.FindNode(Pose2Key(0));
  ASSERT_NE(first, nullptr);
  EXPECT_TRUE(first->fixed);
  EXPECT_EQ(first->value, std::vector<double>({0.0, 0.0, 0.0}));
  EXPECT_EQ(r.ground_truth.at(Pose2Key(0)), first->value);
  int fixed = 0;
  for (const auto& [key, node] : r.graph.nodes()) fixed += node->fixed;
  EXPECT_EQ(fixed, 1);

  // True poses on the lattice, headings multiples of 90 degrees,
  // consecutive poses one step apart along the newer heading.
  for (int k = 0; k < n; ++k) {
    const Pose2 p = TruePose2(r, k);
    EXPECT_NEAR(p.t.x(), std::round(p.t.x()), 1e-12);
    EXPECT_NEAR(p.t.y(), std::round(p.t.y()), 1e-12);
    EXPECT_GE(p.t.minCoeff(), 0.0);
    EXPECT_LE(p.t.maxCoeff(), config.world.grid_size - 1.0);
    const double quarter = p.theta / (M_PI / 2);
    EXPECT_NEAR(quarter, std::round(quarter), 1e-12);
    if (k > 0) {
      const Pose2 d = TruePose2(r, k - 1).Inverse() * p;
      const Eigen::Vector2d step = p.t - TruePose2(r, k - 1).t;
      EXPECT_NEAR(step.norm(), 1.0, 1e-12);
      EXPECT_NEAR(std::cos(p.theta) * step.x() + std::sin(p.theta) * step.y(),
                  1.0, 1e-12);
      EXPECT_LE(std::abs(d.theta), M_PI / 2 + 1e-12);  // No U-turns
                                                       // inside the grid.
    }
  }

  // Odometry: factors 0..n-2 in time order, between k and k+1, and the
  // initial values are their composition (dead reckoning).
  Pose2 dead_reckoning;
  for (int k = 0; k + 1 < n; ++k) {
    const Factor* f = r.graph.FindFactor(r.odometry_factors[k]);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->type, FactorType::kBetweenSE2);
    EXPECT_EQ(f->keys, std::vector<Key>({Pose2Key(k), Pose2Key(k + 1)}));
    dead_reckoning = dead_reckoning * MeasurementPose2(*f);
    const Pose2 node = NodePose2(*r.graph.FindNode(Pose2Key(k + 1)));
    EXPECT_NEAR((node.t - dead_reckoning.t).norm(), 0.0, 1e-9);
    EXPECT_NEAR(NormalizeAngle(node.theta - dead_reckoning.theta), 0.0, 1e-9);
  }
  // Factors in time order: the newer key never decreases.
  int64_t last = 0;
  for (const auto& [id, f] : r.graph.factors()) {
    EXPECT_GE(f.keys[1].id, last);
    last = f.keys[1].id;
  }
  // Loop closures: revisits (same lattice point with radius 0.5), at least
  // min_index_gap apart.
  for (FactorId id : r.loop_closure_factors) {
    const Factor* f = r.graph.FindFactor(id);
    const int i = static_cast<int>(f->keys[0].id);
    const int j = static_cast<int>(f->keys[1].id);
    EXPECT_GE(j - i, config.loop_closures.min_index_gap);
    EXPECT_LE((TruePose2(r, i).t - TruePose2(r, j).t).norm(),
              config.loop_closures.radius);
  }
  // Ground-truth trajectory: stamps k seconds, lifted true poses.
  ASSERT_EQ(r.ground_truth_trajectory.size(), static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const StampedPose& s = r.ground_truth_trajectory[k];
    EXPECT_EQ(s.stamp, k * kNanosecondsPerSecond);
    const Pose3 lifted = LiftPose2(TruePose2(r, k));
    EXPECT_NEAR((s.pose.t - lifted.t).norm(), 0.0, 1e-12);
    EXPECT_NEAR(s.pose.q.angularDistance(lifted.q), 0.0, 1e-9);
  }
}

TEST(SimulatorTest, Grid3dStructure) {
  SimulationConfig config = Config("grid3d", 400, 5);
  SimulationResult r;
  SimulateOrDie(config, &r);
  EXPECT_TRUE(r.is_3d);
  ASSERT_EQ(r.graph.NumNodes(), 400u);
  EXPECT_GT(r.loop_closure_factors.size(), 100u);
  EXPECT_TRUE(r.graph.FindNode(Pose3Key(0))->fixed);
  std::set<std::vector<int>> orientations;
  bool any_vertical = false;
  for (int k = 0; k < 400; ++k) {
    const Pose3 p = TruePose3(r, k);
    const Eigen::Matrix3d rotation = p.q.toRotationMatrix();
    // Axis-aligned rotations, positions on the lattice.
    std::vector<int> signature;
    for (int e = 0; e < 9; ++e) {
      const double v = rotation.data()[e];
      EXPECT_NEAR(v, std::round(v), 1e-12);
      signature.push_back(static_cast<int>(std::round(v)));
    }
    orientations.insert(signature);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(p.t[a], std::round(p.t[a]), 1e-12);
      EXPECT_GE(p.t[a], -1e-12);
      EXPECT_LE(p.t[a], config.world.grid_size - 1.0 + 1e-12);
    }
    if (k > 0) {
      // One step along the newer pose's x axis.
      const Eigen::Vector3d step = p.t - TruePose3(r, k - 1).t;
      EXPECT_NEAR((step - rotation.col(0)).norm(), 0.0, 1e-12);
      any_vertical = any_vertical || std::abs(step.z()) > 0.5;
    }
  }
  // Roll and pitch occur, not only yaw: many of the 24 orientations.
  EXPECT_GE(orientations.size(), 12u);
  EXPECT_TRUE(any_vertical);
}

TEST(SimulatorTest, Sphere3dStructure) {
  SimulationConfig config = Config("sphere3d", 300, 2);
  config.world.poses_per_ring = 30;
  config.loop_closures.probability = 1.0;
  SimulationResult r;
  SimulateOrDie(config, &r);
  EXPECT_TRUE(r.is_3d);
  // The first pose is the identity with its z axis along the outward normal:
  // the center is at (0, 0, -radius) in its frame.
  const Eigen::Vector3d center(0.0, 0.0, -config.world.radius);
  for (int k = 0; k < 300; ++k) {
    const Pose3 p = TruePose3(r, k);
    EXPECT_NEAR((p.t - center).norm(), config.world.radius, 1e-9);
    const Eigen::Matrix3d rotation = p.q.toRotationMatrix();
    EXPECT_NEAR((rotation.col(2) - (p.t - center).normalized()).norm(), 0.0,
                1e-9);
  }
  // Every pose after the first ring closes to the previous ring.
  ASSERT_EQ(r.loop_closure_factors.size(), 300u - 30u);
  for (FactorId id : r.loop_closure_factors) {
    const Factor* f = r.graph.FindFactor(id);
    EXPECT_EQ(f->keys[1].id - f->keys[0].id, 30);
  }
}

// The chi2 of the ground truth under the noisy measurements: every whitened
// residual component is N(0, 1), so per component the mean square is 1
// (standard deviation sqrt(2 / M) over M factors) and the total is chi2 with
// (residual dimensions) degrees of freedom. This catches a wrong information
// scale (e.g. the factor 4 of the SE(3) quaternion-vector error) or noise
// drawn with the wrong spread.
TEST(SimulatorTest, GroundTruthChi2IsChi2Distributed) {
  for (const std::string world : {"grid2d", "grid3d", "sphere3d"}) {
    SCOPED_TRACE(world);
    SimulationConfig config = Config(world, 2000, 11);
    config.odometry = {0.1, 0.02};
    config.loop_closures.noise = {0.03, 0.05};
    SimulationResult r;
    SimulateOrDie(config, &r);
    SetNodeValues(r.ground_truth, &r.graph);
    const int dim = r.is_3d ? 6 : 3;
    for (const auto* ids : {&r.odometry_factors, &r.loop_closure_factors}) {
      const double m = static_cast<double>(ids->size());
      ASSERT_GT(m, 200);
      Eigen::VectorXd mean_square = Eigen::VectorXd::Zero(dim);
      for (FactorId id : *ids) {
        const Eigen::VectorXd res = Residual(r.graph, *r.graph.FindFactor(id));
        mean_square += res.cwiseAbs2() / m;
      }
      for (int d = 0; d < dim; ++d) {
        EXPECT_NEAR(mean_square[d], 1.0, 4.5 * std::sqrt(2.0 / m))
            << "component " << d;
      }
      const double dof = dim * m;
      EXPECT_NEAR(mean_square.sum() * m, dof, 4.0 * std::sqrt(2.0 * dof));
    }
    EXPECT_NEAR(r.graph.Chi2(), dim * r.graph.NumFactors(),
                4.0 * std::sqrt(2.0 * dim * r.graph.NumFactors()));
  }
}

TEST(SimulatorTest, OutliersAreWrongLoopClosures) {
  SimulationConfig config = Config("grid2d", 500, 4);
  config.loop_closures.outlier_fraction = 0.2;
  SimulationResult r;
  SimulateOrDie(config, &r);
  const size_t outliers = r.outlier_factors.size();
  const size_t inliers = r.loop_closure_factors.size() - outliers;
  EXPECT_EQ(outliers, static_cast<size_t>(std::llround(0.2 / 0.8 * inliers)));
  SetNodeValues(r.ground_truth, &r.graph);
  std::vector<double> chi2;
  for (FactorId id : r.outlier_factors) {
    EXPECT_NE(std::find(r.loop_closure_factors.begin(),
                        r.loop_closure_factors.end(), id),
              r.loop_closure_factors.end());
    const Factor* f = r.graph.FindFactor(id);
    EXPECT_GE(f->keys[1].id - f->keys[0].id, 2);
    double c = 0.0;
    ASSERT_TRUE(r.graph.FactorChi2(*f, &c));
    chi2.push_back(c);
  }
  // Random relative poses: far off the truth under the loop-closure noise.
  std::sort(chi2.begin(), chi2.end());
  EXPECT_GT(chi2[chi2.size() / 2], 1000.0);
  // No outliers without the option.
  config.loop_closures.outlier_fraction = 0.0;
  SimulateOrDie(config, &r);
  EXPECT_TRUE(r.outlier_factors.empty());
}

// simulate -> chordal initialization -> optimize recovers the truth: the
// error is a small fraction of the dead-reckoning drift and the final chi2
// is that of a least-squares fit with (m - n) degrees of freedom.
void CheckRecovery(const SimulationConfig& config, double max_rmse) {
  SimulationResult r;
  SimulateOrDie(config, &r);
  const double drift_rmse = PositionRmse(r.graph, r.ground_truth, r.is_3d);
  const OptimizerSummary summary = Solve(&r.graph, InitMethod::kChordal);
  ASSERT_TRUE(summary.usable);
  EXPECT_TRUE(summary.converged) << summary.termination;
  const double rmse = PositionRmse(r.graph, r.ground_truth, r.is_3d);
  EXPECT_LT(rmse, max_rmse);
  EXPECT_LT(rmse, 0.25 * drift_rmse) << "dead reckoning " << drift_rmse;
  const int dim = r.is_3d ? 6 : 3;
  const double dof = dim * (static_cast<double>(r.graph.NumFactors()) -
                            (r.graph.NumNodes() - 1));
  EXPECT_NEAR(summary.final_chi2, dof, 5.0 * std::sqrt(2.0 * dof));
  // The optimum fits the measurements at least as well as the truth.
  const double final_chi2 = r.graph.Chi2();
  SetNodeValues(r.ground_truth, &r.graph);
  EXPECT_LE(final_chi2, r.graph.Chi2());
}

TEST(SimulatorTest, OptimizeRecoversGrid2d) {
  CheckRecovery(Config("grid2d", 500, 1), 0.3);
}

TEST(SimulatorTest, OptimizeRecoversGrid3d) {
  CheckRecovery(Config("grid3d", 500, 1), 0.3);
}

TEST(SimulatorTest, OptimizeRecoversSphere3d) {
  SimulationConfig config = Config("sphere3d", 500, 1);
  config.loop_closures.probability = 1.0;
  CheckRecovery(config, 1.0);
}

// With 10% outlier loop closures, plain least squares is ruined, while DCS on
// the loop closures (started from dead reckoning) lands on the solution that
// the inliers alone give.
void CheckRobustness(const SimulationConfig& config) {
  SimulationResult inliers_only;
  SimulateOrDie(config, &inliers_only);
  ASSERT_GT(inliers_only.outlier_factors.size(), 10u);
  for (FactorId id : inliers_only.outlier_factors) {
    inliers_only.graph.RemoveFactor(id);
  }
  Solve(&inliers_only.graph, InitMethod::kChordal);
  const bool is_3d = inliers_only.is_3d;
  const std::map<Key, std::vector<double>> reference =
      Values(inliers_only.graph);
  const double reference_rmse =
      PositionRmse(inliers_only.graph, inliers_only.ground_truth, is_3d);

  SimulationResult plain;
  SimulateOrDie(config, &plain);
  Solve(&plain.graph, InitMethod::kChordal);
  const double plain_rmse =
      PositionRmse(plain.graph, plain.ground_truth, is_3d);

  SimulationResult robust;
  SimulateOrDie(config, &robust);
  RobustKernelSpec spec;
  std::string error;
  ASSERT_TRUE(ParseRobustKernel("dcs:10", &spec, &error)) << error;
  SetLoss(robust, robust.loop_closure_factors, MakeLoss(spec));
  const OptimizerSummary summary = Solve(&robust.graph, InitMethod::kNone);
  EXPECT_TRUE(summary.converged) << summary.termination;
  const double robust_rmse =
      PositionRmse(robust.graph, robust.ground_truth, is_3d);

  EXPECT_LT(PositionRmse(robust.graph, reference, is_3d), 0.01);
  EXPECT_LT(robust_rmse, 1.1 * reference_rmse + 0.01);
  EXPECT_GT(plain_rmse, 5.0 * robust_rmse);
  EXPECT_GT(plain_rmse, 1.0);
}

TEST(SimulatorTest, RobustKernelRejectsOutliers2d) {
  SimulationConfig config = Config("grid2d", 500, 2);
  config.loop_closures.outlier_fraction = 0.1;
  CheckRobustness(config);
}

TEST(SimulatorTest, RobustKernelRejectsOutliers3d) {
  SimulationConfig config = Config("grid3d", 400, 2);
  config.loop_closures.outlier_fraction = 0.1;
  CheckRobustness(config);
}

TEST(SimulatorTest, SetNodeValuesSetsOnlyKnownKeys) {
  SimulationResult r;
  SimulateOrDie(Config("grid2d", 10, 1), &r);
  std::map<Key, std::vector<double>> values = r.ground_truth;
  values[Pose2Key(99)] = {1.0, 2.0, 3.0};  // Not in the graph: ignored.
  values[Pose3Key(1)] = {1.0, 2.0, 3.0};   // Not in the graph: ignored.
  SetNodeValues(values, &r.graph);
  for (const auto& [key, node] : r.graph.nodes()) {
    EXPECT_EQ(node->value, r.ground_truth.at(key));
  }
  EXPECT_EQ(r.graph.NumNodes(), 10u);
}

}  // namespace
}  // namespace slam
