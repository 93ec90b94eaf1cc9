// `slam inertial` end to end through the binary:
//   * simulated EuRoC folder (slam simulate, world inertial) -> window and
//     batch trajectories, state CSVs, evaluation against the input's ground
//     truth, JSON report with the per-update timing;
//   * the GTSAM imuAndGPSdata.csv (real file, skipped when absent): both
//     estimates pass within a few sigma of the GPS fixes;
//   * covariance CSV (parsed back), NEES in the report, ground-truth start
//     with the truth's bias;
//   * --dump_config round trip; bad input and bad configs fail with a clear
//     message and write nothing.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Cholesky>

#include "apps/inertial_consistency_report.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::DatasetPath;
using testing::Exists;
using testing::ReadText;
using testing::RunSlam;
using testing::TempDir;
using testing::WriteText;

// TUM file -> stamp (s) -> position.
std::map<long long, std::vector<double>> ReadTum(const std::string& path) {
  std::map<long long, std::vector<double>> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z;
    fields >> t >> x >> y >> z;
    out[std::llround(t * 1e6)] = {x, y, z};  // Microseconds.
  }
  return out;
}

int CountLines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

TEST(InertialCommandTest, SimulatedEurocWindowAndBatch) {
  const std::string dir = TempDir();
  WriteText(dir + "/sim.yaml",
            "simulate:\n  seed: 3\n  world:\n    type: inertial\n"
            "  inertial:\n    duration: 20.0\n    position_rate: 5.0\n");
  ASSERT_EQ(RunSlam("simulate --config " + dir + "/sim.yaml -o " + dir + "/sim",
                    dir + "/sim.log"),
            0)
      << ReadText(dir + "/sim.log");
  ASSERT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir +
                        "/out --gt input --report " + dir + "/report.json",
                    dir + "/run.log"),
            0)
      << ReadText(dir + "/run.log");
  const std::string log = ReadText(dir + "/run.log");
  EXPECT_TRUE(Contains(log, "window: 201 keyframes")) << log;
  EXPECT_TRUE(Contains(log, "evaluation of batch")) << log;
  EXPECT_TRUE(Contains(log, "update median")) << log;
  for (const char* name : {"window.tum", "window_filter.tum", "batch.tum",
                           "window_states.csv", "batch_states.csv"}) {
    EXPECT_TRUE(Exists(dir + "/out/" + name)) << name;
  }
  EXPECT_EQ(CountLines(ReadText(dir + "/out/batch_states.csv")), 202);
  const std::string report = ReadText(dir + "/report.json");
  EXPECT_TRUE(Contains(report, "\"median_ms\"")) << report;
  EXPECT_TRUE(Contains(report, "\"ape_translation\"")) << report;
  // Started at the ground truth, the window has no yaw transient.
  WriteText(dir + "/gt_start.yaml",
            "inertial:\n  initial_state: ground_truth\n");
  ASSERT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir +
                        "/out_gt --config " + dir + "/gt_start.yaml",
                    dir + "/run_gt.log"),
            0)
      << ReadText(dir + "/run_gt.log");
  EXPECT_TRUE(Contains(ReadText(dir + "/run_gt.log"), "with initial state"));
  // Both estimates follow the truth (fixes of 0.1 m at 5 Hz).
  const auto truth = ReadTum(dir + "/sim/ground_truth.tum");
  for (const char* name : {"window.tum", "batch.tum"}) {
    const auto est = ReadTum(dir + "/out/" + name);
    ASSERT_EQ(est.size(), 201u);
    double sum = 0.0;
    int n = 0;
    for (const auto& [t, p] : est) {
      auto it = truth.find(t);
      ASSERT_NE(it, truth.end()) << t;
      if (t < 5000000) continue;  // Skip the first 5 s (yaw converging).
      for (int c = 0; c < 3; ++c) sum += std::pow(p[c] - it->second[c], 2);
      ++n;
    }
    EXPECT_LT(std::sqrt(sum / n), 0.15) << name;
  }
}

// Covariance CSV and NEES report: one 15 x 15 positive definite covariance
// per filter keyframe (and per fixed-lag keyframe), parsed back; with --gt
// input the report holds evaluation.window_filter.nees.{position,pose,bias}.
// {mean,median} (raw and yaw-aligned), and the same under window.
// initial_state: ground_truth starts at the truth's bias too (with a tight bias
// prior, the first estimate holds the simulated bias).
TEST(InertialCommandTest, CovarianceCsvNeesReportAndGroundTruthBias) {
  const std::string dir = TempDir();
  WriteText(dir + "/sim.yaml",
            "simulate:\n  seed: 4\n  world:\n    type: inertial\n"
            "  inertial:\n    duration: 15.0\n    position_rate: 5.0\n"
            "    initial_gyro_bias: [0.002, -0.001, 0.0015]\n"
            "    initial_accel_bias: [0.03, -0.02, 0.05]\n");
  ASSERT_EQ(RunSlam("simulate --config " + dir + "/sim.yaml -o " + dir + "/sim",
                    dir + "/sim.log"),
            0)
      << ReadText(dir + "/sim.log");
  WriteText(dir + "/run.yaml",
            "inertial:\n  initial_state: ground_truth\n"
            "  prior_gyro_bias_sigma: 1e-7\n  prior_accel_bias_sigma: 1e-7\n");
  ASSERT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir +
                        "/out --estimator window --gt input --config " + dir +
                        "/run.yaml --report " + dir + "/report.json",
                    dir + "/run.log"),
            0)
      << ReadText(dir + "/run.log");
  const std::string log = ReadText(dir + "/run.log");
  EXPECT_TRUE(Contains(log, "NEES of window_filter")) << log;
  std::vector<TimeNs> stamps;
  std::vector<Eigen::MatrixXd> covs;
  std::string error;
  ASSERT_TRUE(
      ParseCovarianceCsv(ReadText(dir + "/out/covariance_window_filter.csv"),
                         &stamps, &covs, &error))
      << error;
  const auto filter = ReadTum(dir + "/out/window_filter.tum");
  ASSERT_EQ(covs.size(), filter.size());
  ASSERT_GT(covs.size(), 100u);
  size_t k = 0;
  for (const auto& [t_us, p] : filter) {
    EXPECT_EQ(std::llround(stamps[k] * 1e-3), t_us);
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(covs[k]).info(), Eigen::Success);
    ++k;
  }
  // The fixed-lag estimate's covariances: one per keyframe of window.tum.
  std::vector<TimeNs> smoothed_stamps;
  std::vector<Eigen::MatrixXd> smoothed_covs;
  ASSERT_TRUE(ParseCovarianceCsv(ReadText(dir + "/out/covariance_window.csv"),
                                 &smoothed_stamps, &smoothed_covs, &error))
      << error;
  EXPECT_EQ(smoothed_covs.size(), ReadTum(dir + "/out/window.tum").size());
  const YAML::Node report = YAML::LoadFile(dir + "/report.json");
  EXPECT_GT(report["evaluation"]["window"]["nees"]["bias"]["mean"].as<double>(),
            0.0);
  const YAML::Node nees = report["evaluation"]["window_filter"]["nees"];
  ASSERT_TRUE(nees.IsMap()) << ReadText(dir + "/report.json");
  for (const char* block :
       {"position", "pose", "velocity", "bias", "gyro_bias", "accel_bias"}) {
    for (const char* stat : {"mean", "median"}) {
      EXPECT_GT(nees[block][stat].as<double>(), 0.0) << block << " " << stat;
      EXPECT_GT(nees["yaw_aligned"][block][stat].as<double>(), 0.0)
          << block << " " << stat;
      // The ground-truth start knows the yaw from the start: after_yaw is
      // the same keyframes as the whole.
      EXPECT_EQ(nees["after_yaw"][block][stat].as<double>(),
                nees[block][stat].as<double>())
          << block << " " << stat;
    }
  }
  EXPECT_EQ(nees["pose"]["dof"].as<int>(), 6);
  EXPECT_EQ(nees["gyro_bias"]["dof"].as<int>(), 3);
  EXPECT_EQ(nees["after_yaw"]["keyframes"].as<int>(),
            nees["keyframes"].as<int>());
  // The real-time rotation error from there: small from the true start.
  EXPECT_GT(nees["after_yaw"]["rotation_rmse_deg"].as<double>(), 0.0);
  EXPECT_LT(nees["after_yaw"]["rotation_rmse_deg"].as<double>(), 3.0);
  EXPECT_EQ(report["noise"]["gyro_noise_inflation"].as<double>(), 1.0);
  EXPECT_EQ(report["noise"]["accel_noise_density"].as<double>(), 2.0e-3);
  EXPECT_EQ(nees["skip_seconds"].as<double>(), 10.0);
  EXPECT_GT(nees["keyframes"].as<int>(), 20);
  // The first filter state's bias: the simulated initial bias.
  std::ifstream states(dir + "/out/window_filter_states.csv");
  std::string line;
  std::getline(states, line);  // Header.
  std::getline(states, line);
  std::vector<double> v;
  std::stringstream fields(line);
  std::string f;
  while (std::getline(fields, f, ',')) v.push_back(std::stod(f));
  ASSERT_EQ(v.size(), 10u) << line;
  const double expected[6] = {0.002, -0.001, 0.0015, 0.03, -0.02, 0.05};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(v[4 + i], expected[i], 1e-5) << i;
}

TEST(InertialCommandTest, GtsamImuAndGpsRunsEndToEnd) {
  const std::string csv = DatasetPath("imu/gtsam_imuAndGPSdata.csv");
  SLAM_REQUIRE_DATASET(csv);
  const std::string dir = TempDir();
  // GTSAM ImuFactorsExample's noise values; its initial velocity row is not
  // consistent with the data (datasets/imu_io.h), hence the wide prior.
  WriteText(dir + "/gtsam.yaml",
            "inertial:\n"
            "  gyro_noise_density: 2.05689024915e-4\n"
            "  accel_noise_density: 3.924e-4\n"
            "  gyro_random_walk: 1.454441043e-6\n"
            "  accel_random_walk: 4.905e-3\n"
            "  position_sigma: 1.0\n"
            "  prior_velocity_sigma: 2.0\n");
  ASSERT_EQ(RunSlam("inertial -i " + csv + " -o " + dir + "/out --config " +
                        dir + "/gtsam.yaml",
                    dir + "/run.log"),
            0)
      << ReadText(dir + "/run.log");
  EXPECT_TRUE(Contains(ReadText(dir + "/run.log"), "100 fixes (0 skipped)"));
  // The GPS fixes with their stamps (n * 5 ms, n = IMU rows before).
  std::ifstream in(csv);
  std::string line;
  long long imu_rows = 0;
  std::vector<std::pair<long long, std::vector<double>>> fixes;
  while (std::getline(in, line)) {
    if (line.rfind("0,", 0) == 0) ++imu_rows;
    if (line.rfind("1,", 0) == 0) {
      std::vector<double> v;
      std::stringstream fields(line.substr(2));
      std::string f;
      while (std::getline(fields, f, ',')) v.push_back(std::stod(f));
      fixes.push_back({imu_rows * 5000, {v[0], v[1], v[2]}});
    }
  }
  ASSERT_EQ(fixes.size(), 100u);
  for (const char* name : {"window.tum", "batch.tum"}) {
    const auto est = ReadTum(dir + "/out/" + name);
    int matched = 0;
    double worst = 0.0;
    for (const auto& [t, p] : fixes) {
      auto it = est.find(t);
      if (it == est.end()) continue;
      ++matched;
      double d2 = 0.0;
      for (int c = 0; c < 3; ++c) d2 += std::pow(it->second[c] - p[c], 2);
      worst = std::max(worst, std::sqrt(d2));
    }
    EXPECT_GE(matched, 99) << name;
    EXPECT_LT(worst, 4.0) << name;  // GPS sigma 1 m per axis.
  }
}

TEST(InertialCommandTest, DumpConfigRoundTrips) {
  const std::string dir = TempDir();
  WriteText(dir + "/c.yaml",
            "inertial:\n  window_size: 7\n  estimator: window\n"
            "  initial_state: ground_truth\n"
            "  gravity: [0, 0, -9.8]\n  lever_arm: [0.1, 0, 0]\n");
  ASSERT_EQ(RunSlam("inertial --config " + dir + "/c.yaml --dump_config",
                    dir + "/a.yaml"),
            0);
  const std::string first = ReadText(dir + "/a.yaml");
  EXPECT_TRUE(Contains(first, "window_size: 7")) << first;
  EXPECT_TRUE(Contains(first, "initial_state: ground_truth")) << first;
  EXPECT_TRUE(Contains(first, "gravity: [0, 0, -9.8")) << first;
  ASSERT_EQ(RunSlam("inertial --config " + dir + "/a.yaml --dump_config",
                    dir + "/b.yaml"),
            0);
  EXPECT_EQ(first, ReadText(dir + "/b.yaml"));
  // Flags override the file.
  ASSERT_EQ(RunSlam("inertial --config " + dir +
                        "/c.yaml --window_size 12 --dump_config",
                    dir + "/c.out"),
            0);
  EXPECT_TRUE(Contains(ReadText(dir + "/c.out"), "window_size: 12"));
}

TEST(InertialCommandTest, BadInputAndConfigFailCleanly) {
  const std::string dir = TempDir();
  EXPECT_EQ(RunSlam("inertial -o " + dir + "/out", dir + "/usage.log"), 2);
  WriteText(dir + "/bad.yaml", "inertial:\n  window_sise: 5\n");
  EXPECT_EQ(
      RunSlam("inertial --config " + dir + "/bad.yaml -i x -o " + dir + "/out",
              dir + "/key.log"),
      1);
  EXPECT_TRUE(Contains(ReadText(dir + "/key.log"), "window_sise"));
  WriteText(dir + "/range.yaml", "inertial:\n  window_size: 1\n");
  EXPECT_EQ(RunSlam("inertial --config " + dir + "/range.yaml -i x -o " + dir +
                        "/out",
                    dir + "/range.log"),
            1);
  EXPECT_TRUE(Contains(ReadText(dir + "/range.log"), "window_size"));
  // A malformed GTSAM file: the reader's PATH:LINE message, no output.
  WriteText(dir + "/bad.csv",
            "i,0,0,0,0,0,0,1,0,0,0\n0,0,0,9.81,0,0,0\n0,0,zero,9.81,0,0,0\n");
  EXPECT_EQ(RunSlam("inertial -i " + dir + "/bad.csv -o " + dir + "/out",
                    dir + "/csv.log"),
            1);
  EXPECT_TRUE(Contains(ReadText(dir + "/csv.log"), dir + "/bad.csv:3"))
      << ReadText(dir + "/csv.log");
  // Too short to hold two keyframes (no fixes either: allowed here).
  WriteText(dir + "/short.csv",
            "i,0,0,0,0,0,0,1,0,0,0\n0,0,0,9.81,0,0,0\n0,0,0,9.81,0,0,0\n");
  EXPECT_EQ(RunSlam("inertial -i " + dir + "/short.csv -o " + dir +
                        "/out --dead_reckoning",
                    dir + "/short.log"),
            1);
  EXPECT_TRUE(Contains(ReadText(dir + "/short.log"), "keyframe"))
      << ReadText(dir + "/short.log");
  EXPECT_FALSE(Exists(dir + "/out"));
}

}  // namespace
}  // namespace slam
