// Tests of `slam simulate` (apps/simulate_command.cc) through the binary, and
// of its YAML config (apps/simulate_config.h).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/simulate_config.h"
#include "core/graph.h"
#include "datasets/g2o_io.h"
#include "datasets/simulator.h"
#include "datasets/trajectory_io.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::RunSlam;
using ::slam::testing::TempDir;
using ::slam::testing::ReadText;
using ::slam::testing::WriteText;
using ::slam::testing::Exists;

std::string ConfigsDir() {
  return std::string(SLAM_TEST_DATA_DIR) + "/../../configs";
}

void ExpectSameConfig(const SimulationConfig& a, const SimulationConfig& b) {
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.world.type, b.world.type);
  EXPECT_EQ(a.world.num_poses, b.world.num_poses);
  EXPECT_EQ(a.world.step, b.world.step);
  EXPECT_EQ(a.world.grid_size, b.world.grid_size);
  EXPECT_EQ(a.world.turn_probability, b.world.turn_probability);
  EXPECT_EQ(a.world.poses_per_ring, b.world.poses_per_ring);
  EXPECT_EQ(a.world.radius, b.world.radius);
  EXPECT_EQ(a.odometry.sigma_translation, b.odometry.sigma_translation);
  EXPECT_EQ(a.odometry.sigma_rotation, b.odometry.sigma_rotation);
  const SimulationConfig::LoopClosures& la = a.loop_closures;
  const SimulationConfig::LoopClosures& lb = b.loop_closures;
  EXPECT_EQ(la.noise.sigma_translation, lb.noise.sigma_translation);
  EXPECT_EQ(la.noise.sigma_rotation, lb.noise.sigma_rotation);
  EXPECT_EQ(la.radius, lb.radius);
  EXPECT_EQ(la.probability, lb.probability);
  EXPECT_EQ(la.max_per_pose, lb.max_per_pose);
  EXPECT_EQ(la.min_index_gap, lb.min_index_gap);
  EXPECT_EQ(la.outlier_fraction, lb.outlier_fraction);
  EXPECT_EQ(la.outlier_max_translation, lb.outlier_max_translation);
}

// The files written for a config hold exactly what Simulate produces.
void CheckWrittenDataset(const std::string& dir,
                         const SimulationConfig& config) {
  SimulationResult expected;
  std::string error;
  ASSERT_TRUE(Simulate(config, &expected, &error)) << error;

  Graph graph;
  ASSERT_TRUE(ReadG2o(dir + "/graph.g2o", GraphReadOptions(), &graph, nullptr,
                      &error))
      << error;
  ASSERT_EQ(graph.NumNodes(), expected.graph.NumNodes());
  ASSERT_EQ(graph.NumFactors(), expected.graph.NumFactors());
  for (const auto& [key, node] : expected.graph.nodes()) {
    const Node* read = graph.FindNode(key);
    ASSERT_NE(read, nullptr) << key.ToString();
    EXPECT_EQ(read->value, node->value) << key.ToString();
    EXPECT_EQ(read->fixed, node->fixed) << key.ToString();
  }
  auto it = graph.factors().begin();
  for (const auto& [id, factor] : expected.graph.factors()) {
    EXPECT_EQ(it->second.keys, factor.keys);
    EXPECT_EQ(it->second.measurement, factor.measurement);
    EXPECT_EQ(it->second.information, factor.information);
    ++it;
  }

  Graph truth;
  ASSERT_TRUE(ReadG2o(dir + "/ground_truth.g2o", GraphReadOptions(), &truth,
                      nullptr, &error))
      << error;
  ASSERT_EQ(truth.NumNodes(), expected.ground_truth.size());
  EXPECT_EQ(truth.NumFactors(), expected.graph.NumFactors());
  for (const auto& [key, value] : expected.ground_truth) {
    ASSERT_TRUE(truth.HasNode(key));
    EXPECT_EQ(truth.FindNode(key)->value, value) << key.ToString();
  }

  Trajectory tum;
  ASSERT_TRUE(ReadTumTrajectory(dir + "/ground_truth.tum", &tum, &error))
      << error;
  ASSERT_EQ(tum.size(), expected.ground_truth_trajectory.size());
  for (size_t k = 0; k < tum.size(); ++k) {
    const StampedPose& e = expected.ground_truth_trajectory[k];
    EXPECT_EQ(tum[k].stamp, e.stamp);
    EXPECT_NEAR((tum[k].pose.t - e.pose.t).norm(), 0.0, 1e-12);
    EXPECT_NEAR(tum[k].pose.q.angularDistance(e.pose.q), 0.0, 1e-9);
  }

  const std::string outliers = dir + "/outliers.txt";
  if (expected.outlier_factors.empty()) {
    EXPECT_FALSE(Exists(outliers));
  } else {
    ASSERT_TRUE(Exists(outliers));
    std::istringstream in(ReadText(outliers));
    std::string line;
    size_t count = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      int64_t index = -1, from = -1, to = -1;
      fields >> index >> from >> to;
      ASSERT_LT(count, expected.outlier_factors.size());
      const FactorId id = expected.outlier_factors[count];
      EXPECT_EQ(index, id);
      // The index is the position among the EDGE lines of the file.
      auto edge = graph.factors().begin();
      std::advance(edge, index);
      EXPECT_EQ(edge->second.keys[0].id, from);
      EXPECT_EQ(edge->second.keys[1].id, to);
      ++count;
    }
    EXPECT_EQ(count, expected.outlier_factors.size());
  }
}

TEST(SimulateCommandTest, WritesGraphTruthAndTrajectory2d) {
  const std::string dir = TempDir() + "/out";
  const std::string log = TempDir() + "/log";
  ASSERT_EQ(RunSlam("simulate -o " + dir + " --num_poses 200 --seed 5", log),
            0)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("200 poses"), std::string::npos)
      << ReadText(log);
  const std::string g2o = ReadText(dir + "/graph.g2o");
  EXPECT_NE(g2o.find("VERTEX_SE2 "), std::string::npos);
  EXPECT_NE(g2o.find("FIX 0"), std::string::npos);
  SimulationConfig config;
  config.world.num_poses = 200;
  config.seed = 5;
  CheckWrittenDataset(dir, config);
}

TEST(SimulateCommandTest, WritesSphere3dWithOutliers) {
  const std::string dir = TempDir() + "/out";
  const std::string log = TempDir() + "/log";
  ASSERT_EQ(RunSlam("simulate -o " + dir +
                        " --world sphere3d --num_poses 150 --seed 3"
                        " --outlier_fraction 0.2 --loop_probability 1",
                    log),
            0)
      << ReadText(log);
  EXPECT_NE(ReadText(dir + "/graph.g2o").find("VERTEX_SE3:QUAT "),
            std::string::npos);
  SimulationConfig config;
  config.world.type = "sphere3d";
  config.world.num_poses = 150;
  config.seed = 3;
  config.loop_closures.outlier_fraction = 0.2;
  config.loop_closures.probability = 1.0;
  CheckWrittenDataset(dir, config);

  // A later run without outliers into the same directory removes the
  // stale outliers.txt.
  ASSERT_TRUE(Exists(dir + "/outliers.txt"));
  ASSERT_EQ(RunSlam("simulate -o " + dir + " --world sphere3d --num_poses 150",
                    log),
            0)
      << ReadText(log);
  EXPECT_FALSE(Exists(dir + "/outliers.txt"));
}

TEST(SimulateCommandTest, FlagsOverrideEveryNoiseSetting) {
  const std::string dir = TempDir() + "/out";
  const std::string log = TempDir() + "/log";
  ASSERT_EQ(RunSlam("simulate -o " + dir +
                        " --world grid3d --num_poses 120 --seed 9"
                        " --odometry_sigma_t 0.2 --odometry_sigma_r 0.03"
                        " --loop_sigma_t 0.07 --loop_sigma_r 0.04",
                    log),
            0)
      << ReadText(log);
  SimulationConfig config;
  config.world.type = "grid3d";
  config.world.num_poses = 120;
  config.seed = 9;
  config.odometry = {0.2, 0.03};
  config.loop_closures.noise = {0.07, 0.04};
  CheckWrittenDataset(dir, config);
}

TEST(SimulateCommandTest, DumpConfigRoundTrips) {
  const std::string tmp = TempDir();
  const std::string a = tmp + "/a.yaml";
  const std::string b = tmp + "/b.yaml";
  ASSERT_EQ(RunSlam("simulate --dump_config --world grid3d --num_poses 123"
                    " --seed 18446744073709551615 --outlier_fraction 0.15"
                    " --odometry_sigma_r 0.0123 --loop_probability 0.3 > " +
                    a),
            0);
  SimulationConfig expected;
  expected.world.type = "grid3d";
  expected.world.num_poses = 123;
  expected.seed = 18446744073709551615ull;
  expected.loop_closures.outlier_fraction = 0.15;
  expected.odometry.sigma_rotation = 0.0123;
  expected.loop_closures.probability = 0.3;
  SimulationConfig loaded;
  std::string error;
  ASSERT_TRUE(LoadSimulationConfig(a, &loaded, &error)) << error;
  ExpectSameConfig(loaded, expected);
  EXPECT_EQ(ReadText(a), SimulationConfigToYaml(expected));

  ASSERT_EQ(RunSlam("simulate --config " + a + " --dump_config > " + b), 0);
  EXPECT_EQ(ReadText(a), ReadText(b));
}

TEST(SimulateCommandTest, DefaultsDumpAsTheDocumentedConfig) {
  const std::string out = TempDir() + "/defaults.yaml";
  ASSERT_EQ(RunSlam("simulate --dump_config > " + out), 0);
  EXPECT_EQ(ReadText(out), SimulationConfigToYaml(SimulationConfig()));
  // configs/simulate_2d.yaml is the default, written out.
  SimulationConfig loaded;
  std::string error;
  ASSERT_TRUE(LoadSimulationConfig(ConfigsDir() + "/simulate_2d.yaml",
                                   &loaded, &error))
      << error;
  ExpectSameConfig(loaded, SimulationConfig());
}

TEST(SimulateCommandTest, ShippedConfigsLoadAndSimulate) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ConfigsDir())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("simulate", 0) != 0) continue;
    SCOPED_TRACE(name);
    ++count;
    SimulationConfig config;
    std::string error;
    ASSERT_TRUE(LoadSimulationConfig(entry.path().string(), &config, &error))
        << error;
    if (config.world.type == "inertial") {  // IMU data, no pose graph.
      InertialData data;
      ASSERT_TRUE(SimulateInertial(config.inertial, &data, &error)) << error;
      EXPECT_GT(data.imu.size(), 1000u);
      continue;
    }
    SimulationResult result;
    ASSERT_TRUE(Simulate(config, &result, &error)) << error;
    EXPECT_GT(result.loop_closure_factors.size(), 100u);
  }
  EXPECT_GE(count, 2);
}

TEST(SimulateCommandTest, ConfigFileThenFlags) {
  const std::string tmp = TempDir();
  const std::string config = tmp + "/c.yaml";
  const std::string out = tmp + "/dump.yaml";
  WriteText(config,
            "simulate:\n  seed: 3\n  world:\n    num_poses: 100\n"
            "    type: sphere3d\n  loop_closures:\n    radius: 2.5\n");
  SimulationConfig expected;
  expected.seed = 3;                    // From the file.
  expected.world.type = "sphere3d";     // From the file.
  expected.world.num_poses = 50;        // The flag wins.
  expected.loop_closures.radius = 2.5;  // From the file.
  ASSERT_EQ(RunSlam("simulate --dump_config --config " + config +
                    " --num_poses 50 > " + out),
            0);
  SimulationConfig dumped;
  std::string error;
  ASSERT_TRUE(LoadSimulationConfig(out, &dumped, &error)) << error;
  ExpectSameConfig(dumped, expected);
}

// Through the binary: exit code, message naming the file and the key, and
// no output written (also with --dump_config).
TEST(SimulateCommandTest, UnknownYamlKeyFailsNamingFileAndKey) {
  const std::string tmp = TempDir();
  const std::string log = tmp + "/log";
  const std::string config = tmp + "/bad.yaml";
  const std::string dir = tmp + "/out";
  WriteText(config, "simulate:\n  world:\n    num_poses: 10\n"
                    "    typo_key: 1\n");
  EXPECT_EQ(RunSlam("simulate --config " + config + " -o " + dir, log), 2);
  const std::string message = ReadText(log);
  EXPECT_NE(message.find(config + ":4: unknown key 'typo_key'"),
            std::string::npos)
      << message;
  EXPECT_FALSE(Exists(dir));
  EXPECT_EQ(RunSlam("simulate --dump_config --config " + config, log), 2);
  EXPECT_NE(ReadText(log).find("typo_key"), std::string::npos);
  EXPECT_EQ(ReadText(log).find("seed:"), std::string::npos);  // No YAML.
}

// The loader: every kind of bad file fails with a message naming the file and
// what is wrong, and leaves nothing half-applied that matters (it fails).
TEST(SimulateCommandTest, BadConfigFilesAreErrors) {
  const std::string tmp = TempDir();
  struct Case {
    const char* yaml;
    const char* expected;  // In the message, besides the file name.
  };
  const Case cases[] = {
      {"simulate:\n  world:\n    num_poses: 10\n    typo_key: 1\n",
       ":4: unknown key 'typo_key'"},
      {"simulate:\n  seed: 1\n  landmarks: {}\n", "'landmarks'"},
      {"simualte:\n  seed: 1\n", "'simualte'"},
      {"simulate:\n  odometry:\n    sigma: 1\n", "'sigma'"},
      {"simulate:\n  loop_closures:\n    outliers: 1\n", "'outliers'"},
      {"simulate:\n  world: grid2d\n", "expected a mapping"},
      {"simulate:\n  world:\n    num_poses: many\n", "'num_poses' (line 3)"},
      {"simulate:\n  seed: -3\n", "'seed'"},
      {"simulate:\n  loop_closures:\n    outlier_fraction: 1.5\n",
       "simulate.loop_closures.outlier_fraction"},
      {"simulate:\n  world:\n    type: torus\n", "'torus'"},
      {"simulate: [1, 2\n", ":2:"},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.yaml);
    const std::string path = tmp + "/bad" + std::to_string(index++) + ".yaml";
    WriteText(path, c.yaml);
    SimulationConfig config;
    std::string error;
    EXPECT_FALSE(LoadSimulationConfig(path, &config, &error));
    EXPECT_EQ(error.rfind(path, 0), 0u) << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
  }
  SimulationConfig config;
  std::string error;
  EXPECT_FALSE(LoadSimulationConfig(tmp + "/missing.yaml", &config, &error));
  EXPECT_NE(error.find("missing.yaml"), std::string::npos) << error;
  // An empty file or section keeps the defaults.
  WriteText(tmp + "/empty.yaml", "simulate:\n");
  EXPECT_TRUE(LoadSimulationConfig(tmp + "/empty.yaml", &config, &error))
      << error;
  ExpectSameConfig(config, SimulationConfig());
}

TEST(SimulateCommandTest, UsageErrors) {
  const std::string log = TempDir() + "/log";
  EXPECT_EQ(RunSlam("simulate", log), 2);  // No -o.
  EXPECT_NE(ReadText(log).find("-o DIR"), std::string::npos) << ReadText(log);
  EXPECT_EQ(RunSlam("simulate -o " + TempDir() + "/x extra", log), 2);
  EXPECT_NE(ReadText(log).find("extra"), std::string::npos) << ReadText(log);
  EXPECT_EQ(RunSlam("simulate -o " + TempDir() + "/x --world torus", log), 2);
  EXPECT_NE(ReadText(log).find("torus"), std::string::npos) << ReadText(log);
  EXPECT_EQ(RunSlam("simulate -o " + TempDir() + "/x --num_poses 1", log), 2);
  EXPECT_NE(ReadText(log).find("num_poses"), std::string::npos)
      << ReadText(log);
}

}  // namespace
}  // namespace slam
