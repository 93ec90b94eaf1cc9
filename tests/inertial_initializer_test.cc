// Initialization of inertial estimation without ground truth
// (frontends/inertial/inertial_initializer.h) and the robustness of the
// estimators built on it, on simulated data with known answers:
//   * a still start (gyroscope bias from it) and a true yaw of 140 degrees;
//     a moving start with the same yaw and 1 Hz fixes;
//   * window and batch from the initializer follow the truth; the batch run
//     alone reaches the optimum of the batch started from the window;
//   * a trajectory without horizontal acceleration: yaw never observable,
//     said so;
//   * no fixes (refused unless --dead_reckoning), sparse fixes and IMU gaps
//     (warnings naming the file and line), through the binary;
//   * keyframes at the IMU rate and at half of it;
//   * real data (EuRoC V1_02, 40 s, skipped when absent): default start
//     within 10 % of the ground-truth start's ATE, 10 Hz and 1 Hz fixes;
//   * flights as a MAV flies them in a small room, with the EuRoC noise
//     settings (configs/inertial_euroc.yaml) in the simulation and the
//     estimator: a gentle one (horizontal accelerations 0.2-0.5 m/s^2, slow
//     yaw changes) aligns its yaw within 10 s; on flights of different
//     character (gentle, brisk, long) the real-time estimate's rotation error
//     stays within 3 deg once aligned and its NEES of position and bias
//     within the targets; hover and pure vertical motion leave the yaw
//     unobservable, and say so.
#include "frontends/inertial/inertial_initializer.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "apps/inertial_config.h"
#include "datasets/imu_io.h"
#include "datasets/inertial_simulator.h"
#include "datasets/inertial_trajectory.h"
#include "frontends/inertial/inertial_consistency.h"
#include "frontends/inertial/inertial_estimator.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::ReadText;
using testing::RunSlam;
using testing::TempDir;

constexpr double kDeg = M_PI / 180.0;

// The Lissajous figure eight rotated by `yaw` about the vertical, after
// `still` seconds at rest at its start; the motion ramps up smoothly over
// `ramp` seconds (time warp s(t) with s' a smoothstep from 0 to 1), so that
// the readings stay exact.
class StillThenMoving : public SmoothTrajectory {
 public:
  StillThenMoving(double still, double ramp, double yaw,
                  const LissajousParams& params = {})
      : still_(still), ramp_(ramp), yaw_(yaw), lissajous_(params) {}

  TrajectorySample Evaluate(double t) const override {
    double s = 0.0, ds = 0.0, dds = 0.0;
    const double x = ramp_ > 0.0 ? (t - still_) / ramp_ : 1.0;
    if (x >= 1.0) {
      s = 0.5 * ramp_ + (t - still_ - ramp_);
      ds = 1.0;
    } else if (x > 0.0) {
      s = ramp_ * (x * x * x - 0.5 * x * x * x * x);
      ds = 3 * x * x - 2 * x * x * x;
      dds = (6 * x - 6 * x * x) / ramp_;
    }
    const TrajectorySample l = lissajous_.Evaluate(s);
    const Eigen::Matrix3d rz =
        Eigen::AngleAxisd(yaw_, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The body rate in the body frame of a time-warped rotation is scaled;
    // its derivative does not enter the readings.
    TrajectorySample out;
    out.pose = Pose3(rz * l.pose.t, Eigen::Quaterniond(rz) * l.pose.q);
    out.velocity = rz * l.velocity * ds;
    out.acceleration = rz * (l.acceleration * ds * ds + l.velocity * dds);
    out.omega = l.omega * ds;
    return out;
  }
  double duration() const override { return 1e9; }

 private:
  double still_, ramp_, yaw_;
  LissajousTrajectory lissajous_;
};

InertialData Simulate(const SmoothTrajectory& trajectory, double duration,
                      double fix_rate, unsigned seed = 1) {
  InertialSimulationConfig config;
  config.duration = duration;
  config.position_rate = fix_rate;
  config.seed = seed;
  InertialData data;
  std::string error;
  EXPECT_TRUE(SimulateInertial(config, trajectory, &data, &error)) << error;
  data.has_initial_state = false;  // As from a file: no ground truth start.
  return data;
}

double RotationErrorDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return a.angularDistance(b) / kDeg;
}

double PositionRmse(const InertialData& data,
                    const std::vector<InertialState>& states) {
  double sum = 0.0;
  size_t g = 0;
  for (const InertialState& s : states) {
    while (data.ground_truth[g].stamp < s.stamp) ++g;
    sum += (s.state.pose.t - data.ground_truth[g].pose.t).squaredNorm();
  }
  return std::sqrt(sum / states.size());
}

double RotationRmseDeg(const InertialData& data,
                       const std::vector<InertialState>& states, size_t from) {
  double sum = 0.0;
  size_t g = 0;
  for (size_t k = from; k < states.size(); ++k) {
    while (data.ground_truth[g].stamp < states[k].stamp) ++g;
    sum += std::pow(
        RotationErrorDeg(states[k].state.pose.q, data.ground_truth[g].pose.q),
        2);
  }
  return std::sqrt(sum / (states.size() - from));
}

TEST(InertialInitializerTest, StillStartGivesGyroBiasTiltAndThenTheYaw) {
  const StillThenMoving trajectory(3.0, 2.0, 140.0 * kDeg);
  const InertialData data = Simulate(trajectory, 20.0, 10.0);
  InertialOptions options;
  InertialInitialization init;
  std::string error;
  ASSERT_TRUE(InitializeInertial(data, options, &init, &error)) << error;
  std::printf("%s\n", init.summary.c_str());
  EXPECT_TRUE(init.still_start);
  EXPECT_NEAR(init.still_seconds, 3.0, 0.5);
  const InertialGroundTruth& truth = data.ground_truth.front();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(init.state.bias[i], truth.bias[i], 5e-4) << i;
  }
  ASSERT_TRUE(init.yaw_observable);
  // Yaw needs horizontal acceleration: not before the motion starts.
  const double t_obs =
      NsToSeconds(init.yaw_observable_stamp - data.imu.front().stamp);
  EXPECT_GT(t_obs, 3.0);
  EXPECT_LT(t_obs, 8.0);
  // Within the yaw sigma it claims (the alignment's, doubled), and a few
  // degrees.
  const double rotation_error =
      RotationErrorDeg(init.state.state.pose.q, truth.pose.q);
  EXPECT_LT(rotation_error, init.yaw_sigma / kDeg);
  EXPECT_LT(rotation_error, 6.0);
  EXPECT_LT((init.state.state.pose.t - truth.pose.t).norm(), 0.1);
  EXPECT_LT(init.state.state.velocity.norm(), 1e-9);  // At rest.
  EXPECT_LT(init.yaw_sigma, 2.0 * kAlignmentMaxYawSigma);
}

TEST(InertialInitializerTest, MovingStartAlignsFromSparseFixes) {
  const StillThenMoving trajectory(0.0, 0.0, 140.0 * kDeg);
  const InertialData data = Simulate(trajectory, 30.0, 1.0);
  InertialOptions options;
  InertialInitialization init;
  std::string error;
  ASSERT_TRUE(InitializeInertial(data, options, &init, &error)) << error;
  std::printf("%s\n", init.summary.c_str());
  EXPECT_FALSE(init.still_start);
  ASSERT_TRUE(init.yaw_observable);
  const InertialGroundTruth& truth = data.ground_truth.front();
  EXPECT_LT(RotationErrorDeg(init.state.state.pose.q, truth.pose.q), 10.0);
  EXPECT_LT((init.state.state.velocity - truth.velocity).norm(), 0.3);
}

// A vertical and sideways-free motion (constant horizontal velocity, body
// rotating about the vertical only at a constant rate): no horizontal
// acceleration, so the fixes cannot give the heading.
class ConstantVelocity : public SmoothTrajectory {
 public:
  TrajectorySample Evaluate(double t) const override {
    TrajectorySample s;
    s.pose = Pose3(Eigen::Vector3d(1.0 * t, 0.5 * t, 2.0),
                   Eigen::Quaterniond(Eigen::AngleAxisd(
                       2.0 + 0.05 * t, Eigen::Vector3d::UnitZ())));
    s.velocity = Eigen::Vector3d(1.0, 0.5, 0.0);
    s.omega = Eigen::Vector3d(0, 0, 0.05);
    return s;
  }
  double duration() const override { return 1e9; }
};

TEST(InertialInitializerTest, YawNeverObservableIsSaidAndShownInCovariance) {
  const InertialData data = Simulate(ConstantVelocity(), 10.0, 5.0);
  InertialOptions options;
  options.newest_covariance = true;
  InertialInitialization init;
  std::string error;
  ASSERT_TRUE(InitializeInertial(data, options, &init, &error)) << error;
  EXPECT_FALSE(init.yaw_observable);
  EXPECT_TRUE(Contains(init.summary, "NOT observable")) << init.summary;
  InertialRun run;
  ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error)) << error;
  EXPECT_FALSE(run.yaw_observable);
  EXPECT_EQ(run.filter_yaw_unknown, run.filter.size());
  // The newest state's yaw standard deviation (rotation about the body z,
  // which is vertical here; covariance order: rho, phi, ...) starts at the
  // prior's 180 degrees and stays large for the first second. (It then
  // shrinks: the linearised window reads some heading information into
  // the accelerometer noise and the rotating bias; measured 30 degrees
  // after 1 s, 6 after 5 s.)
  EXPECT_GT(std::sqrt(run.newest_covariance[0](5, 5)), 90.0 * kDeg);
  EXPECT_GT(std::sqrt(run.newest_covariance[10](5, 5)), 20.0 * kDeg);
  const Eigen::MatrixXd& c = run.newest_covariance.back();
  EXPECT_LT(std::sqrt(c(3, 3)), 5.0 * kDeg);  // Roll known (gravity).
}

TEST(InertialInitializerTest, WindowAndBatchFromTheInitializerFollowTheTruth) {
  const StillThenMoving trajectory(2.0, 2.0, 140.0 * kDeg);
  const InertialData data = Simulate(trajectory, 40.0, 10.0, 2);
  InertialOptions options;
  std::string error;
  InertialRun window, batch, batch_alone;
  ASSERT_TRUE(RunSlidingWindow(data, options, &window, nullptr, &error))
      << error;
  ASSERT_TRUE(window.yaw_observable);
  ASSERT_GT(window.filter_yaw_unknown, 0u);
  ASSERT_TRUE(RunBatch(data, options, window.smoothed, &batch, nullptr, &error))
      << error;
  ASSERT_TRUE(RunBatch(data, options, {}, &batch_alone, nullptr, &error))
      << error;
  const double ate_window = PositionRmse(data, window.smoothed);
  const double ate_filter = PositionRmse(data, window.filter);
  const double ate_batch = PositionRmse(data, batch.smoothed);
  const double ate_alone = PositionRmse(data, batch_alone.smoothed);
  std::printf("ATE window %.4f filter %.4f batch %.4f batch alone %.4f m\n",
              ate_window, ate_filter, ate_batch, ate_alone);
  EXPECT_LT(ate_window, 0.1);
  EXPECT_LT(ate_filter, 0.2);
  EXPECT_LT(ate_batch, 0.1);
  // The real-time estimate is right once the yaw is observable.
  EXPECT_LT(RotationRmseDeg(data, window.filter, window.filter_yaw_unknown),
            3.0);
  EXPECT_LT(RotationRmseDeg(data, window.smoothed, 0), 3.0);
  // Batch alone and window-then-batch: the same optimum.
  EXPECT_NEAR(batch_alone.final_chi2, batch.final_chi2,
              1e-5 * batch.final_chi2);
  ASSERT_EQ(batch_alone.smoothed.size(), batch.smoothed.size());
  for (size_t k = 0; k < batch.smoothed.size(); ++k) {
    EXPECT_LT(
        (batch_alone.smoothed[k].state.pose.t - batch.smoothed[k].state.pose.t)
            .norm(),
        1e-4);
    EXPECT_LT(RotationErrorDeg(batch_alone.smoothed[k].state.pose.q,
                               batch.smoothed[k].state.pose.q),
              1e-3);
  }
}

TEST(InertialInitializerTest, KeyframesAtTheImuRateAndHalfOfIt) {
  const StillThenMoving trajectory(1.0, 1.0, 40.0 * kDeg);
  const InertialData data = Simulate(trajectory, 6.0, 10.0, 3);
  for (double rate : {200.0, 100.0}) {
    InertialOptions options;
    options.keyframe_rate_hz = rate;
    std::string error;
    InertialRun window, batch;
    ASSERT_TRUE(RunSlidingWindow(data, options, &window, nullptr, &error))
        << rate << " Hz: " << error;
    ASSERT_TRUE(RunBatch(data, options, {}, &batch, nullptr, &error))
        << rate << " Hz: " << error;
    EXPECT_NEAR(static_cast<double>(batch.smoothed.size()), 6.0 * rate + 1,
                2.0);
    EXPECT_LT(PositionRmse(data, batch.smoothed), 0.1) << rate;
    EXPECT_LT(PositionRmse(data, window.smoothed), 0.2) << rate;
  }
}

// Through the binary: the data checks.
std::string WriteSimulated(const InertialData& data, const std::string& dir) {
  std::string error;
  EXPECT_TRUE(WriteEurocInertial(dir, data, &error)) << error;
  return dir;
}

TEST(InertialInitializerTest, NoFixesAreRefusedUnlessDeadReckoningIsAsked) {
  const std::string dir = TempDir();
  const StillThenMoving trajectory(1.0, 1.0, 0.0);
  InertialData data = Simulate(trajectory, 5.0, 0.0);
  ASSERT_TRUE(data.positions.empty());
  WriteSimulated(data, dir + "/sim");
  EXPECT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir + "/out",
                    dir + "/run.log"),
            1);
  const std::string log = ReadText(dir + "/run.log");
  EXPECT_TRUE(Contains(log, "no position fixes")) << log;
  EXPECT_TRUE(Contains(log, "--dead_reckoning")) << log;
  EXPECT_FALSE(testing::Exists(dir + "/out/window.tum"));
  EXPECT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir +
                        "/out --dead_reckoning --report " + dir + "/r.json",
                    dir + "/dr.log"),
            0)
      << ReadText(dir + "/dr.log");
  EXPECT_TRUE(Contains(ReadText(dir + "/dr.log"), "warning: dead reckoning"));
  EXPECT_TRUE(Contains(ReadText(dir + "/r.json"), "\"yaw_observable\": false"))
      << ReadText(dir + "/r.json");
}

TEST(InertialInitializerTest, SparseFixesAndImuGapsAreReported) {
  const StillThenMoving trajectory(1.0, 1.0, 1.0);
  InertialData data = Simulate(trajectory, 30.0, 1.0);
  // Fixes only in the first 8 s and the last 5 s: 19 s without.
  std::vector<PositionFix> kept;
  for (const PositionFix& f : data.positions) {
    const double t = NsToSeconds(f.stamp - data.imu.front().stamp);
    if (t < 8.0 || t > 25.0) kept.push_back(f);
  }
  data.positions = kept;
  // Drop 10 readings (50 ms) after reading 1000.
  data.imu.erase(data.imu.begin() + 1001, data.imu.begin() + 1011);
  std::vector<InertialGroundTruth> truth;
  for (const InertialGroundTruth& g : data.ground_truth) {
    if (g.stamp <= data.imu[1000].stamp || g.stamp >= data.imu[1001].stamp) {
      truth.push_back(g);
    }
  }
  data.ground_truth = truth;
  const std::vector<std::string> warnings = InertialDataWarnings(data);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_TRUE(Contains(warnings[0], "IMU reading 1001: IMU gap of 55.0 ms"))
      << warnings[0];
  EXPECT_TRUE(Contains(warnings[1], "19.0 s without a position fix"))
      << warnings[1];
  const std::string dir = TempDir();
  WriteSimulated(data, dir + "/sim");
  ASSERT_EQ(RunSlam("inertial -i " + dir + "/sim -o " + dir + "/out",
                    dir + "/run.log"),
            0)
      << ReadText(dir + "/run.log");
  const std::string log = ReadText(dir + "/run.log");
  // The header line is line 1: reading 1001 (0-based) is on line 1003.
  EXPECT_TRUE(Contains(log, "warning: " + dir +
                                "/sim/mav0/imu0/data.csv:1003: IMU gap of 55.0 "
                                "ms"))
      << log;
  EXPECT_TRUE(Contains(log, "warning: fixes too sparse: 19.0 s")) << log;
  EXPECT_TRUE(Contains(log, "initializer: ")) << log;
}

// The report's APE translation RMSE of `name` (window, window_filter,
// batch) in the "evaluation" section; -1 if missing.
double ReportAte(const std::string& report, const std::string& name) {
  size_t at = report.find("\"evaluation\"");
  if (at == std::string::npos) return -1.0;
  at = report.find("\"" + name + "\": {", at);
  if (at == std::string::npos) return -1.0;
  at = report.find("\"ape_translation\"", at);
  if (at == std::string::npos) return -1.0;
  at = report.find("\"rmse\": ", at);
  if (at == std::string::npos) return -1.0;
  return std::stod(report.substr(at + 8, 30));
}

// EuRoC V1_02 (first 40 s, fixes made from the ground truth at 10 Hz, and
// thinned to 1 Hz), with configs/inertial_euroc.yaml: started by the
// initializer, every estimate's ATE (no alignment) is within 10 % of the run
// started at the ground truth (the
// issue's bar; before the initializer, at 10 Hz, 0.081 / 0.247 / 0.039
// against 0.045 / 0.082 / 0.041). With the 10 Hz fixes the real-time
// estimate from the default start is also consistent (the bar: mean
// NEES after the first 10 s within 30 % of 3 for the position, within a
// factor 1.5 of 6 for pose and bias; README: 3.67 / 7.52 / 5.22; with the
// data sheet noise 5.34 / 57.4 / 48.8, and before the initializer
// 4.67 / 20.1 / 62.3, both fail it).
TEST(InertialInitializerTest, EurocDefaultStartMatchesTheGroundTruthStart) {
  const std::string euroc = testing::DatasetPath("imu_euroc_V1_02_40s");
  SLAM_REQUIRE_DATASET(euroc + "/mav0/imu0/data.csv");
  const std::string dir = TempDir();
  // The noise settings users run EuRoC with (configs/inertial_euroc.yaml:
  // the data sheet densities inflated for the MAV's vibration); the
  // ground-truth start adds only initial_state.
  const std::string euroc_config =
      ReadText(testing::ConfigPath("inertial_euroc.yaml"));
  const size_t section = euroc_config.find("\ninertial:\n");
  ASSERT_NE(section, std::string::npos);
  std::string gt_config = euroc_config;
  gt_config.insert(section + std::string("\ninertial:\n").size(),
                   "  initial_state: ground_truth\n");
  testing::WriteText(dir + "/default.yaml",
                     euroc_config + "eval:\n  align: none\n");
  testing::WriteText(dir + "/gt.yaml", gt_config + "eval:\n  align: none\n");
  // The 1 Hz copy: every 10th fix.
  InertialData data;
  std::string error;
  ASSERT_TRUE(ReadEurocInertial(euroc, &data, &error)) << error;
  std::vector<PositionFix> thinned;
  for (size_t f = 0; f < data.positions.size(); f += 10) {
    thinned.push_back(data.positions[f]);
  }
  data.positions = thinned;
  ASSERT_TRUE(WriteEurocInertial(dir + "/euroc_1hz", data, &error)) << error;
  for (const std::string& input : {euroc, dir + "/euroc_1hz"}) {
    std::string reports[2];
    const char* names[2] = {"default", "gt"};
    for (int i = 0; i < 2; ++i) {
      const std::string base = dir + "/" + names[i];
      ASSERT_EQ(RunSlam("inertial -i " + input + " -o " + base +
                            "_out --gt input --config " + base +
                            ".yaml --report " + base + ".json",
                        base + ".log"),
                0)
          << ReadText(base + ".log");
      reports[i] = ReadText(base + ".json");
    }
    EXPECT_TRUE(
        Contains(ReadText(dir + "/default.log"), "initializer: still start"));
    for (const char* name : {"window", "window_filter", "batch"}) {
      const double ate = ReportAte(reports[0], name);
      const double ate_gt = ReportAte(reports[1], name);
      std::printf("%s, %s: ATE %.4f m (ground-truth start %.4f m)\n",
                  input.c_str(), name, ate, ate_gt);
      ASSERT_GT(ate_gt, 0.0) << name;
      EXPECT_GT(ate, 0.0) << name;
      EXPECT_LT(ate, 1.1 * ate_gt) << input << " " << name;
    }
    if (input != euroc) continue;
    const YAML::Node nees =
        YAML::Load(reports[0])["evaluation"]["window_filter"]["nees"];
    ASSERT_TRUE(nees.IsMap()) << reports[0];
    const double position = nees["position"]["mean"].as<double>();
    const double pose = nees["pose"]["mean"].as<double>();
    const double bias = nees["bias"]["mean"].as<double>();
    std::printf(
        "default start, 10 Hz fixes: mean NEES position %.2f (3), "
        "pose %.2f (6), bias %.2f (6)\n",
        position, pose, bias);
    EXPECT_GT(position, 0.7 * 3.0);
    EXPECT_LT(position, 1.3 * 3.0);
    EXPECT_GT(pose, 6.0 / 1.5);
    EXPECT_LT(pose, 1.5 * 6.0);
    EXPECT_GT(bias, 6.0 / 1.5);
    EXPECT_LT(bias, 1.5 * 6.0);
  }
}

// The settings users run EuRoC with (configs/inertial_euroc.yaml), as the
// estimator uses them (data sheet densities x inflation).
InertialOptions EurocOptions() {
  InertialConfig config;
  std::string error;
  EXPECT_TRUE(LoadInertialConfig(testing::ConfigPath("inertial_euroc.yaml"),
                                 &config, &error))
      << error;
  return EffectiveInertialOptions(config);
}

// A flight with the EuRoC noise: the simulated readings get the densities
// the EuRoC config gives the estimator, biases of the ADIS16448's size (gyro
// a few 0.01 rad/s, accelerometer about 0.1 m/s^2, drawn per seed), 10 Hz
// fixes of 0.1 m per axis.
InertialData SimulateFlight(const SmoothTrajectory& trajectory, double duration,
                            unsigned seed,
                            const Eigen::Vector3d* gyro_bias = nullptr) {
  const InertialOptions options = EurocOptions();
  InertialSimulationConfig config;
  config.duration = duration;
  config.position_rate = 10.0;
  config.position_sigma = options.position_sigma;
  config.noise = options.noise;
  config.seed = seed;
  testing::TestRng rng(seed);
  for (int i = 0; i < 3; ++i) {
    config.initial_gyro_bias[i] = rng.Uniform(-0.03, 0.03);
    config.initial_accel_bias[i] = rng.Uniform(-0.1, 0.1);
  }
  if (gyro_bias != nullptr) config.initial_gyro_bias = *gyro_bias;
  InertialData data;
  std::string error;
  EXPECT_TRUE(SimulateInertial(config, trajectory, &data, &error)) << error;
  data.has_initial_state = false;
  return data;
}

// A gentle flight: a Lissajous figure in a room of 5 x 4 m with
// horizontal accelerations of 0.2-0.5 m/s^2 most of the time (peaks 0.31
// and 0.41 m/s^2 per axis), height +- 0.3 m, yaw swinging +- 35 deg over a
// minute, the tilt of a multirotor accelerating that gently.
LissajousParams GentleFlight() {
  LissajousParams p;
  p.center = Eigen::Vector3d(0.0, 0.0, 1.5);
  p.amplitude = Eigen::Vector3d(2.5, 2.0, 0.3);
  p.frequency = Eigen::Vector3d(0.35, 0.45, 0.3);
  p.phase = Eigen::Vector3d(0.0, 0.0, 0.0);
  p.yaw_rate = 0.0;
  p.yaw_amplitude = 0.6;
  p.yaw_frequency = 0.1;
  p.pitch_amplitude = 0.03;
  p.pitch_frequency = 0.35;
  p.roll_amplitude = 0.03;
  p.roll_frequency = 0.45;
  return p;
}

// A brisker flight: twice the gentle figure's speed, yaw turning steadily.
LissajousParams BriskFlight() {
  LissajousParams p = GentleFlight();
  p.frequency *= 1.6;
  p.yaw_rate = 0.15;
  p.yaw_amplitude = 0.3;
  p.yaw_frequency = 0.3;
  p.pitch_amplitude = 0.08;
  p.roll_amplitude = 0.08;
  return p;
}

// The real-time estimate's rotation error (rmse, deg) and NEES after the
// first 15 s (the yaw is known by then on these flights).
bool FiguresAfter15s(const InertialData& data, const InertialRun& run,
                     double* rotation_rmse, NeesSummary* nees,
                     std::string* error) {
  constexpr double kSkipSeconds = 15.0;
  size_t from = 0;
  while (from < run.filter.size() &&
         NsToSeconds(run.filter[from].stamp - data.imu.front().stamp) <
             kSkipSeconds) {
    ++from;
  }
  *rotation_rmse = RotationRmseDeg(data, run.filter, from);
  NeesOptions nees_options;
  nees_options.skip_seconds = kSkipSeconds;
  return SummarizeNees(run.filter, run.newest_covariance, data.ground_truth,
                       nees_options, nees, error);
}

// Initializes from a start in motion (prints the summary): no still start
// and the yaw observable.
::testing::AssertionResult InitializeMovingStart(const InertialData& data,
                                                 const InertialOptions& options,
                                                 unsigned seed,
                                                 InertialInitialization* init) {
  std::string error;
  if (!InitializeInertial(data, options, init, &error)) {
    return ::testing::AssertionFailure() << error;
  }
  std::printf("seed %u: %s\n", seed, init->summary.c_str());
  if (init->still_start || !init->yaw_observable) {
    return ::testing::AssertionFailure() << init->summary;
  }
  return ::testing::AssertionSuccess();
}

// The sliding window's run on a flight and its FiguresAfter15s.
struct FlightFigures {
  InertialRun run;
  double rotation_rmse = 0.0;
  NeesSummary nees;
};

// Runs the sliding window on `data`, takes FiguresAfter15s and prints them.
::testing::AssertionResult RunAndFiguresAfter15s(const InertialData& data,
                                                 const InertialOptions& options,
                                                 unsigned seed,
                                                 FlightFigures* figures) {
  std::string error;
  if (!RunSlidingWindow(data, options, &figures->run, nullptr, &error) ||
      !FiguresAfter15s(data, figures->run, &figures->rotation_rmse,
                       &figures->nees, &error)) {
    return ::testing::AssertionFailure() << error;
  }
  const NeesSummary& nees = figures->nees;
  std::printf(
      "seed %u: yaw observable after %.2f s, rotation %.2f deg rmse (after "
      "15 s), NEES position %.2f pose %.2f bias %.2f\n",
      seed, figures->run.yaw_observable_after_seconds, figures->rotation_rmse,
      nees.position.mean, nees.pose.mean, nees.bias.mean);
  return ::testing::AssertionSuccess();
}

// The benchmark's gentle entry (configs/benchmarks/inertial.yaml: a moving
// start on GentleFlight's figure, its biases, the EuRoC noise) flown with
// seeds 27 and 29. The alignment's (cos, sin) of the yaw came out with norms
// of 1.28-1.43 at sigmas of 0.10-0.15 from 12 s on, and a fixed 0.8-1.25
// band on the norm threw those fits away: the yaw was known only after
// 25.3 and 16.2 s (bias NEES 14.9 and 13.8 over the flight). The norm is
// now tested against its own sigma (kUnitNormSigmas): both within 15 s.
TEST(InertialFlightTest, AlignmentNormWithinItsSigmaKeepsTheFit) {
  InertialOptions options = EurocOptions();
  for (unsigned seed : {27u, 29u}) {
    InertialSimulationConfig config;
    config.duration = 90.0;  // The benchmark's (the fixes' noise is drawn
                             // after the readings').
    config.position_rate = 10.0;
    config.position_sigma = options.position_sigma;
    config.noise = options.noise;
    config.seed = seed;
    config.initial_gyro_bias = Eigen::Vector3d(-0.002, 0.021, 0.076);
    config.initial_accel_bias = Eigen::Vector3d(-0.013, 0.103, 0.093);
    config.trajectory = GentleFlight();
    InertialData data;
    std::string error;
    ASSERT_TRUE(SimulateInertial(config, &data, &error)) << error;
    data.has_initial_state = false;
    InertialRun run;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    std::printf("seed %u: %s\n", seed, run.initialization_summary.c_str());
    ASSERT_TRUE(run.yaw_observable) << run.initialization_summary;
    EXPECT_LT(run.yaw_observable_after_seconds, 15.0) << "seed " << seed;
  }
}

TEST(InertialFlightTest, GentleFlightAlignsTheYawWithinTenSeconds) {
  const InertialOptions options = EurocOptions();
  for (unsigned seed : {11u, 12u}) {
    const StillThenMoving trajectory(1.0, 4.0, 140.0 * kDeg, GentleFlight());
    const InertialData data = SimulateFlight(trajectory, 60.0, seed);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    std::printf("seed %u: %s; yaw observable after %.2f s\n", seed,
                run.initialization_summary.c_str(),
                run.yaw_observable_after_seconds);
    ASSERT_TRUE(run.yaw_observable) << run.initialization_summary;
    EXPECT_LT(run.yaw_observable_after_seconds, 10.0);
    const double rmse =
        RotationRmseDeg(data, run.filter, run.filter_yaw_unknown);
    std::printf(
        "seed %u: real-time rotation error %.2f deg rmse once the yaw "
        "is observable\n",
        seed, rmse);
    EXPECT_LT(rmse, 3.0);
  }
}

// Flights of different character from the initializer's start, with the
// EuRoC settings: each flight's yaw known within 15 s, its real-time
// estimate's NEES (after 15 s) of position within 2.1-3.9 and of pose and
// bias within a factor 2 of 6; on average over the flights, the rotation
// error (rmse after 15 s) within 3 deg and the bias NEES within a factor
// 1.5 of 6 (the gentle flights carry little yaw information: the window's
// yaw sigma stays near 3 deg on them). (One
// flight's NEES is the mean over strongly correlated keyframes: a single
// run scatters more than the mean over runs. Before the alignment modelled
// the biases, a trial of these flights with a 2 s ramp aligned the second
// one 14 deg off while claiming a sigma of 6 deg: rotation 7.0 deg, bias
// NEES 12.6 on it.)
TEST(InertialFlightTest,
     RealTimeEstimateIsConsistentOnFlightsOfDifferentKinds) {
  InertialOptions options = EurocOptions();
  options.newest_covariance = true;
  struct Flight {
    const char* name;
    LissajousParams params;
    double duration;
    unsigned seed;
  };
  const Flight flights[] = {{"gentle", GentleFlight(), 60.0, 21},
                            {"gentle", GentleFlight(), 60.0, 22},
                            {"brisk", BriskFlight(), 60.0, 23},
                            {"gentle, long", GentleFlight(), 150.0, 24}};
  double rotation = 0.0, bias = 0.0;
  for (const Flight& flight : flights) {
    const StillThenMoving trajectory(1.0, 4.0, -60.0 * kDeg, flight.params);
    const InertialData data =
        SimulateFlight(trajectory, flight.duration, flight.seed);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    ASSERT_TRUE(run.yaw_observable) << run.initialization_summary;
    double rmse = 0.0;
    NeesSummary nees;
    ASSERT_TRUE(FiguresAfter15s(data, run, &rmse, &nees, &error)) << error;
    std::printf(
        "%s flight, seed %u: yaw observable after %.2f s, rotation "
        "%.2f deg rmse, NEES position %.2f pose %.2f bias %.2f\n",
        flight.name, flight.seed, run.yaw_observable_after_seconds, rmse,
        nees.position.mean, nees.pose.mean, nees.bias.mean);
    EXPECT_LT(run.yaw_observable_after_seconds, 15.0) << flight.name;
    EXPECT_GT(nees.position.mean, 2.1) << flight.name;
    EXPECT_LT(nees.position.mean, 3.9) << flight.name;
    for (double value : {nees.pose.mean, nees.bias.mean}) {
      EXPECT_GT(value, 6.0 / 2.0) << flight.name;
      EXPECT_LT(value, 6.0 * 2.0) << flight.name;
    }
    rotation += rmse / std::size(flights);
    bias += nees.bias.mean / std::size(flights);
  }
  std::printf(
      "mean over the flights: rotation %.2f deg rmse, bias NEES "
      "%.2f\n",
      rotation, bias);
  EXPECT_LT(rotation, 3.0);
  EXPECT_GT(bias, 6.0 / 1.5);
  EXPECT_LT(bias, 6.0 * 1.5);
}

// A flight already under way when the log starts: 1.3 m/s, turning at
// 0.06 rad/s with nearly no acceleration, so the readings of its first
// second look like a body at rest with a gyro bias of the turn rate. The
// fixes show the motion (1.3 m in that second): the start is not still, the
// gyro bias is not taken from the readings and the velocity comes from the
// alignment. (Before the fixes' velocity was checked, the still test took
// the first second, the gyro bias took the turn and the window stayed
// inconsistent: rotation 30-60 deg rmse, bias NEES in the hundreds.)
TEST(InertialFlightTest, SteadilyMovingStartIsNotTakenForStill) {
  InertialOptions options = EurocOptions();
  options.newest_covariance = true;
  for (unsigned seed : {41u, 42u}) {
    const StillThenMoving trajectory(0.0, 0.0, -60.0 * kDeg, GentleFlight());
    const InertialData data = SimulateFlight(trajectory, 60.0, seed);
    const InertialGroundTruth& truth = data.ground_truth.front();
    ASSERT_GT(truth.velocity.norm(), 1.2);
    InertialInitialization init;
    ASSERT_TRUE(InitializeMovingStart(data, options, seed, &init));
    // The velocity from the alignment, nearer the truth than a still
    // start's zero. (Its claimed sigma is smaller than the error on seed 42:
    // 0.06 m/s against 0.56, aligned 13.4 s in; the window recovers.)
    const double velocity_error =
        (init.state.state.velocity - truth.velocity).norm();
    std::printf("seed %u: start velocity error %.2f m/s, sigma %.2f\n", seed,
                velocity_error, init.velocity_sigma);
    EXPECT_LT(velocity_error, 0.5 * truth.velocity.norm());
    FlightFigures figures;
    ASSERT_TRUE(RunAndFiguresAfter15s(data, options, seed, &figures));
    const InertialRun& run = figures.run;
    const double rmse = figures.rotation_rmse;
    const NeesSummary& nees = figures.nees;
    // A moving start learns the gyro bias (its prior: the sensor's turn-on
    // bias, 0.05 rad/s in the EuRoC config) before the heading: 12.4 and
    // 13.0 s since the alignment models the integrated IMU noise (14.0 and
    // 16.8 s with the fix noise alone; 9.8 and 13.4 s when the prior was
    // 0.01 rad/s, too narrow for the EuRoC unit's 0.076 rad/s).
    EXPECT_LT(run.yaw_observable_after_seconds, 20.0);
    EXPECT_LT(rmse, 8.0);
    EXPECT_LT(nees.pose.mean, 6.0 * 2.0);
    EXPECT_LT(nees.bias.mean, 6.0 * 2.0);
    EXPECT_LT(nees.position.mean, 3.9);
  }
}

// A moving start with the gyro bias of the EuRoC ADIS16448 (its ground truth
// on V1_02: 0.076 rad/s about z, 0.021 about y), far outside the 0.01 rad/s
// the moving start's prior used to give it. The alignment integrated the
// readings with the prior's bias, the heading it found drifted with the
// bias (0.076 rad/s is 44 deg in 10 s) and the window started from a bias
// it believed to 0.01 rad/s: the benchmark's gentle flight (90 s) had a
// rotation error of 17.5 deg rmse after 15 s, bias NEES 46.8. Now the
// alignment re-integrates with its own gyro bias estimate, the prior is the
// sensor's turn-on bias (configs/inertial_euroc.yaml) and the window starts
// from the alignment's bias and sigma.
TEST(InertialFlightTest, MovingStartWithTheEurocGyroBiasEstimatesTheBias) {
  InertialOptions options = EurocOptions();
  options.newest_covariance = true;
  const Eigen::Vector3d gyro_bias(-0.0022, 0.0207, 0.0758);
  for (unsigned seed : {51u, 52u}) {
    const StillThenMoving trajectory(0.0, 0.0, -60.0 * kDeg, GentleFlight());
    InertialData data = SimulateFlight(trajectory, 60.0, seed, &gyro_bias);
    InertialInitialization init;
    ASSERT_TRUE(InitializeMovingStart(data, options, seed, &init));
    EXPECT_LT(NsToSeconds(init.yaw_observable_stamp - data.imu.front().stamp),
              15.0);
    const double z_error = std::abs(init.state.bias[2] - gyro_bias.z());
    std::printf("seed %u: start gyro bias z error %.4f rad/s, sigma %.4f\n",
                seed, z_error, init.gyro_bias_sigma);
    EXPECT_LT(z_error, 0.25 * gyro_bias.z());
    FlightFigures figures;
    ASSERT_TRUE(RunAndFiguresAfter15s(data, options, seed, &figures));
    EXPECT_LT(figures.rotation_rmse, 8.0);
    EXPECT_GT(figures.nees.bias.mean, 6.0 / 1.5);
    EXPECT_LT(figures.nees.bias.mean, 6.0 * 1.5);
    EXPECT_LT(figures.nees.pose.mean, 6.0 * 1.5);
  }
}

// The alignment's sigmas are those the window starts from: they must cover
// its errors. The gentle figure started in motion with the EuRoC unit's
// gyro bias: gravity turns the tilt random walk of the gyroscope's white
// noise (16x the data sheet in flight) into position errors of metres,
// correlated across the fixes, that a fit weighted by the fix noise alone
// partly explains with the biases and the yaw, and believes. Now the
// alignment is a generalised least squares under that noise; seeds 53-82
// (30 flights, by hand): all aligned after 10-15 s, the largest z bias
// error 1.95 of its sigma, the largest rotation error 1.2 of the yaw sigma
// handed on (2.4 of the fit's own). Before, with the fix noise alone: seeds
// 53-55 aligned after 13.9-15.0 s, seed 56 never within its 30 s (its bias
// Gauss-Newton lost the fit), and on the benchmark's gentle flight
// (scripts/benchmark_inertial.py) the alignment found a z bias of 0.040
// rad/s against 0.076 with a fit sigma several times smaller.
TEST(InertialFlightTest, MovingStartAlignmentSigmasCoverItsErrors) {
  const InertialOptions options = EurocOptions();
  const Eigen::Vector3d gyro_bias(-0.0022, 0.0207, 0.0758);
  for (unsigned seed : {53u, 54u, 55u, 56u}) {
    const StillThenMoving trajectory(0.0, 0.0, -60.0 * kDeg, GentleFlight());
    const InertialData data =
        SimulateFlight(trajectory, 30.0, seed, &gyro_bias);
    InertialInitialization init;
    ASSERT_TRUE(InitializeMovingStart(data, options, seed, &init));
    const InertialGroundTruth& truth = data.ground_truth.front();
    const double z_error = std::abs(init.state.bias[2] - truth.bias[2]);
    const double rotation_error =
        RotationErrorDeg(init.state.state.pose.q, truth.pose.q) * kDeg;
    std::printf(
        "seed %u: gyro bias z error %.4f rad/s, sigma %.4f; rotation error "
        "%.1f deg, yaw sigma %.1f deg\n",
        seed, z_error, init.gyro_bias_sigma, rotation_error / kDeg,
        init.yaw_sigma / kDeg);
    EXPECT_LT(z_error, 3.0 * init.gyro_bias_sigma) << seed;
    EXPECT_LT(rotation_error, 3.0 * init.yaw_sigma) << seed;
  }
}

// Before the yaw is known the window runs without yaw information from an
// arbitrary heading (radians off). Its prior, linearised at that heading,
// held the information about it that the data brought, so the data's later
// pull towards the true heading could not turn the linearised chain and
// turned it through the z gyro bias instead: on these gentle moving starts
// with the EuRoC unit's gyro bias, the z bias went 0.27 / 0.15 rad/s off
// with a sigma of 0.02 (12 / 6 sigma; seeds 5 / 63, 12 s in). Now that
// prior may not know the heading better than 60 degrees while the window's
// own yaw sigma is above 10 (inertial_estimator.cc, CapYawInformation):
// 1.9 / 1.9 sigma at worst (1.9 / 2.4 since that pass restarts from the
// rough alignment, WindowWithoutYawRestartsFromTheRoughAlignment).
TEST(InertialFlightTest, WindowWithoutYawKeepsItsGyroBiasWithinItsSigma) {
  InertialOptions options = EurocOptions();
  options.newest_covariance = true;
  const Eigen::Vector3d gyro_bias(-0.0022, 0.0207, 0.0758);
  for (unsigned seed : {5u, 63u}) {
    const StillThenMoving trajectory(0.0, 0.0, 0.0, GentleFlight());
    const InertialData data =
        SimulateFlight(trajectory, 60.0, seed, &gyro_bias);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    ASSERT_GT(run.filter_yaw_unknown, 50u) << run.initialization_summary;
    double worst = 0.0, worst_time = 0.0;
    for (size_t k = 0; k < run.filter_yaw_unknown; ++k) {
      InertialGroundTruth truth;
      ASSERT_TRUE(InterpolateGroundTruth(data.ground_truth, run.filter[k].stamp,
                                         200000000, &truth));
      const double z_error =
          std::abs(InertialStateError(run.filter[k], truth)[11]);
      const double ratio =
          z_error / std::sqrt(run.newest_covariance[k](11, 11));
      if (ratio > worst) {
        worst = ratio;
        worst_time = NsToSeconds(run.filter[k].stamp - data.imu.front().stamp);
      }
    }
    std::printf(
        "seed %u: yaw known after %.2f s; before that the z gyro bias error "
        "reached %.2f sigma (%.1f s)\n",
        seed, run.yaw_observable_after_seconds, worst, worst_time);
    EXPECT_LT(worst, 3.0) << seed;
  }
}

// Hovering in place, or moving only up and down: no horizontal
// acceleration, so neither the alignment nor the window can know the
// heading; both say so.
class VerticalOnly : public SmoothTrajectory {
 public:
  explicit VerticalOnly(double amplitude) : amplitude_(amplitude) {}
  TrajectorySample Evaluate(double t) const override {
    constexpr double kW = 0.8;  // rad/s
    TrajectorySample s;
    s.pose = Pose3(
        Eigen::Vector3d(1.0, 2.0, 1.5 + amplitude_ * std::sin(kW * t)),
        Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())));
    s.velocity = Eigen::Vector3d(0.0, 0.0, amplitude_ * kW * std::cos(kW * t));
    s.acceleration =
        Eigen::Vector3d(0.0, 0.0, -amplitude_ * kW * kW * std::sin(kW * t));
    return s;
  }
  double duration() const override { return 1e9; }

 private:
  double amplitude_;
};

TEST(InertialFlightTest, HoverAndVerticalMotionLeaveTheYawUnobservable) {
  const InertialOptions options = EurocOptions();
  for (double amplitude : {0.0, 0.5}) {
    const InertialData data = SimulateFlight(VerticalOnly(amplitude), 40.0, 31);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    std::printf("vertical amplitude %.1f m: %s\n", amplitude,
                run.initialization_summary.c_str());
    EXPECT_FALSE(run.yaw_observable) << amplitude;
    EXPECT_EQ(run.filter_yaw_unknown, run.filter.size()) << amplitude;
    EXPECT_TRUE(Contains(run.initialization_summary, "NOT observable"))
        << run.initialization_summary;
  }
}

// Before the yaw is known the window's real-time estimates come from a pass
// without yaw information. Started at an arbitrary heading (radians off),
// that pass maps the horizontal accelerations in the wrong direction and
// fits them with tilt, which the x / y gyro and the accelerometer biases
// then carry, and keep. On these 20 s gentle moving starts with the EuRoC
// unit's gyro bias the bias NEES between the alignment's first rough yaw
// (sigma below kYawHintSigma, 7-8 s in) and the yaw being known (11-13 s)
// was 14.3 / 65.0 / 206 (seeds 61 / 69 / 72; pose 3.1 / 56 / 125). Now that
// pass restarts from the rough alignment (inertial_estimator.h): 7.3 / 5.4 /
// 5.1 (pose 3.6 / 3.6 / 4.7); 6.2 / 3.7 / 4.4 once the restarts stopped
// counting the alignment's fixes twice (InertialInitialization::unaligned_*).
// By hand over seeds 5, 61-73 (20 s and 60 s flights; the stretch exists on 11
// and 14 of them): mean 32.6 -> 6.6 and 23.5 -> 6.1, worst 206 -> 11.7 and 106
// -> 9.0; one flight got worse (seed 5, 20 s: 6.7 -> 11.7).
TEST(InertialFlightTest, WindowWithoutYawRestartsFromTheRoughAlignment) {
  InertialOptions options = EurocOptions();
  options.newest_covariance = true;
  const Eigen::Vector3d gyro_bias(-0.0022, 0.0207, 0.0758);
  double mean = 0.0;
  const unsigned seeds[] = {61u, 69u, 72u};
  for (unsigned seed : seeds) {
    const StillThenMoving trajectory(0.0, 0.0, 0.0, GentleFlight());
    const InertialData data =
        SimulateFlight(trajectory, 20.0, seed, &gyro_bias);
    InertialInitialization init;
    ASSERT_TRUE(InitializeMovingStart(data, options, seed, &init));
    ASSERT_NE(init.rough, nullptr);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    NeesOptions nees_options;
    nees_options.skip_seconds = 0.0;
    NeesSummary nees;
    ASSERT_TRUE(SummarizeNees(run.filter, run.newest_covariance,
                              data.ground_truth, nees_options, &nees, &error))
        << error;
    ASSERT_EQ(nees.per_keyframe.size(), run.filter.size());
    double bias = 0.0, pose = 0.0;
    int count = 0;
    for (size_t k = 0; k < run.filter_yaw_unknown; ++k) {
      if (run.filter[k].stamp < init.yaw_hint_stamp) continue;
      bias += nees.per_keyframe[k].bias;
      pose += nees.per_keyframe[k].pose;
      ++count;
    }
    ASSERT_GT(count, 10) << run.initialization_summary;
    bias /= count;
    pose /= count;
    std::printf(
        "seed %u: rough yaw after %.2f s, yaw known after %.2f s; in "
        "between NEES bias %.2f pose %.2f (%d keyframes)\n",
        seed, NsToSeconds(init.yaw_hint_stamp - data.imu.front().stamp),
        run.yaw_observable_after_seconds, bias, pose, count);
    EXPECT_LT(bias, 6.0 * 2.0) << seed;
    EXPECT_GT(bias, 6.0 / 2.0) << seed;
    EXPECT_LT(pose, 6.0 * 2.0) << seed;
    mean += bias / std::size(seeds);
  }
  std::printf("mean bias NEES %.2f\n", mean);
  EXPECT_LT(mean, 6.0 * 1.5);
  EXPECT_GT(mean, 6.0 / 1.5);
}

// The pass restarted from the rough yaw is converged at every update: its
// heading still moves by tens of degrees per update there (a 1 Hz keyframe
// brings a second of new horizontal acceleration), and LM, which rejects its
// first Gauss-Newton steps along the heading, stopped at the window's
// 10-iteration cap. The flight of scripts/benchmark_inertial.py's 200 s,
// 1 Hz keyframe entry (simulator defaults, seed 1; its first 15 s): rough yaw
// at 7 s (29 deg +- 14 off), yaw known at 9 s; the keyframe at 8 s was
// published 25 deg off, 18 deg from that window's own optimum (the same run
// with an iteration cap of 200), 7 deg off. Now the same as the optimum.
TEST(InertialFlightTest, PassRestartedFromTheRoughYawIsConverged) {
  InertialSimulationConfig config;
  config.duration = 200.0;
  config.position_rate = 1.0;
  config.seed = 1;
  InertialData data;
  std::string error;
  ASSERT_TRUE(SimulateInertial(config, &data, &error)) << error;
  data.has_initial_state = false;  // As from a file: the initializer starts.
  const TimeNs end = data.imu.front().stamp + SecondsToNs(15.0);
  auto after_end = [&](const auto& x) { return x.stamp > end; };
  data.imu.erase(std::find_if(data.imu.begin(), data.imu.end(), after_end),
                 data.imu.end());
  data.positions.erase(
      std::find_if(data.positions.begin(), data.positions.end(), after_end),
      data.positions.end());
  InertialOptions options;
  options.keyframe_rate_hz = 1.0;
  InertialInitialization init;
  ASSERT_TRUE(InitializeInertial(data, options, &init, &error)) << error;
  ASSERT_NE(init.rough, nullptr) << init.summary;
  InertialRun run, converged;
  ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error)) << error;
  InertialOptions unlimited = options;
  unlimited.window.max_iterations = 200;
  ASSERT_TRUE(RunSlidingWindow(data, unlimited, &converged, nullptr, &error))
      << error;
  ASSERT_EQ(run.filter.size(), converged.filter.size());
  int count = 0;
  for (size_t k = 0; k < run.filter_yaw_unknown; ++k) {
    if (run.filter[k].stamp < init.yaw_hint_stamp) continue;
    InertialGroundTruth truth;
    ASSERT_TRUE(InterpolateGroundTruth(data.ground_truth, run.filter[k].stamp,
                                       200000000, &truth));
    const double off = RotationErrorDeg(run.filter[k].state.pose.q,
                                        converged.filter[k].state.pose.q);
    std::printf(
        "%.0f s: rotation error %.1f deg, %.1f deg from the optimum's %.1f\n",
        NsToSeconds(run.filter[k].stamp - data.imu.front().stamp),
        RotationErrorDeg(run.filter[k].state.pose.q, truth.pose.q), off,
        RotationErrorDeg(converged.filter[k].state.pose.q, truth.pose.q));
    EXPECT_LT(off, 1.0) << k;
    ++count;
  }
  EXPECT_GE(count, 2) << run.initialization_summary;
}

}  // namespace
}  // namespace slam
