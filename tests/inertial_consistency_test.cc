// Consistency of the inertial estimates (frontends/inertial/
// inertial_consistency.h) and its outputs (apps/inertial_consistency_report.h):
//   * the NEES error is the right (body-frame) perturbation of
//     core/conventions.h: errors drawn from N(0, P) in that tangent (random
//     poses, a covariance with cross terms) give back the drawn vector and a
//     mean NEES equal to the dimension; P off by a factor 2 is detected;
//   * end to end on simulated IMU + fixes with a consistent start: the
//     sliding window's newest-state NEES (position 3, pose 6, bias 6 dof)
//     averaged over seeds and keyframes is within a factor 1.4 of the
//     dimension, and the same errors under the covariance scaled by 2 or 1/2
//     are not;
//   * ground-truth interpolation, the yaw-offset estimate (a reference
//     rotated by a constant yaw is recognised and removed), the covariance
//     CSV round trip and its errors, and the initial bias settings (config
//     keys read, dumped, validated, and used as the first bias prior).
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "apps/inertial_config.h"
#include "apps/inertial_consistency_report.h"
#include "core/lie.h"
#include "frontends/inertial/inertial_consistency.h"
#include "frontends/inertial/inertial_estimator.h"
#include "gtest/gtest.h"
#include "tests/test_inertial_simulation.h"
#include "tests/test_random.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::TempDir;
using testing::TestRng;
using testing::WriteText;

// truth = estimate [+] e (core/conventions.h: right perturbation).
InertialGroundTruth Perturb(const InertialState& x,
                            const Eigen::Matrix<double, 15, 1>& e) {
  InertialGroundTruth t;
  t.stamp = x.stamp;
  t.pose = Pose3(
      x.state.pose.t + x.state.pose.q * e.segment<3>(0),
      x.state.pose.q * QuaternionExp<double>(Eigen::Vector3d(e.segment<3>(3))));
  t.velocity = x.state.velocity + e.segment<3>(6);
  t.bias = x.bias + e.segment<6>(9);
  return t;
}

TEST(InertialNeesTest, RightPerturbationErrorsGiveMeanNeesEqualToDimension) {
  TestRng rng(7);
  constexpr int kSamples = 4000;
  InertialNees sum, sum_double, sum_half;
  for (int s = 0; s < kSamples; ++s) {
    InertialState x;
    x.stamp = s;
    x.state.pose = rng.RandomPose3(50.0);
    x.state.velocity = 3.0 * rng.Normal3();
    for (int i = 0; i < 6; ++i) x.bias[i] = 0.1 * rng.Normal();
    // Strongly anisotropic in the body frame, with cross terms: an error
    // taken in the world frame or on the left would not match it.
    Eigen::MatrixXd p = rng.SpdMatrix(15, 1e-4);
    p.block(0, 0, 3, 3).diagonal() += Eigen::Vector3d(1e-2, 1e-4, 1e-6);
    const Eigen::MatrixXd l = p.llt().matrixL();
    Eigen::Matrix<double, 15, 1> z;
    for (int i = 0; i < 15; ++i) z[i] = rng.Normal();
    const Eigen::Matrix<double, 15, 1> e = l * z;
    const Eigen::Matrix<double, 15, 1> back =
        InertialStateError(x, Perturb(x, e));
    ASSERT_LT((back - e).norm(), 1e-9 * (1.0 + 50.0 * e.norm()));
    InertialNees n, n2, nh;
    ASSERT_TRUE(ComputeInertialNees(back, p, &n));
    ASSERT_TRUE(ComputeInertialNees(back, 2.0 * p, &n2));
    ASSERT_TRUE(ComputeInertialNees(back, 0.5 * p, &nh));
    for (auto [acc, v] : {std::pair(&sum, n), std::pair(&sum_double, n2),
                          std::pair(&sum_half, nh)}) {
      acc->position += v.position / kSamples;
      acc->pose += v.pose / kSamples;
      acc->velocity += v.velocity / kSamples;
      acc->bias += v.bias / kSamples;
      acc->gyro_bias += v.gyro_bias / kSamples;
      acc->accel_bias += v.accel_bias / kSamples;
    }
  }
  // Standard deviation of the mean of 4000 chi2(k): sqrt(2k / 4000), at most
  // 0.055 (k = 6); bounds at about 4 of those.
  EXPECT_NEAR(sum.position, 3.0, 0.16);
  EXPECT_NEAR(sum.pose, 6.0, 0.22);
  EXPECT_NEAR(sum.velocity, 3.0, 0.16);
  EXPECT_NEAR(sum.bias, 6.0, 0.22);
  EXPECT_NEAR(sum.gyro_bias, 3.0, 0.16);
  EXPECT_NEAR(sum.accel_bias, 3.0, 0.16);
  EXPECT_NEAR(sum_half.accel_bias, 6.0, 0.32);
  EXPECT_NEAR(sum_double.pose, 3.0, 0.11);
  EXPECT_NEAR(sum_half.pose, 12.0, 0.44);
  // Not positive definite: refused.
  InertialNees n;
  EXPECT_FALSE(ComputeInertialNees(Eigen::Matrix<double, 15, 1>::Ones(),
                                   Eigen::MatrixXd::Zero(15, 15), &n));
}

InertialData Simulate(unsigned seed, const InertialOptions& options) {
  return testing::SimulateConsistentStart(seed, 20.0, 2.0, options);
}

TEST(InertialNeesTest, SimulatedWindowNeesMatchesDimensionAndCatchesFactorTwo) {
  InertialOptions options;
  options.newest_covariance = true;
  NeesOptions nees_options;
  nees_options.skip_seconds = 5.0;
  constexpr int kSeeds = 10;
  double position = 0.0, pose = 0.0, bias = 0.0;
  double pose_double = 0.0, pose_half = 0.0, bias_double = 0.0, bias_half = 0.0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const InertialData data = Simulate(200 + seed, options);
    InertialRun run;
    std::string error;
    ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
        << error;
    NeesSummary s, s2, sh;
    ASSERT_TRUE(SummarizeNees(run.filter, run.newest_covariance,
                              data.ground_truth, nees_options, &s, &error))
        << error;
    EXPECT_GT(s.keyframes, 140);
    std::vector<Eigen::MatrixXd> doubled = run.newest_covariance,
                                 halved = run.newest_covariance;
    for (Eigen::MatrixXd& c : doubled) c *= 2.0;
    for (Eigen::MatrixXd& c : halved) c *= 0.5;
    ASSERT_TRUE(SummarizeNees(run.filter, doubled, data.ground_truth,
                              nees_options, &s2, &error));
    ASSERT_TRUE(SummarizeNees(run.filter, halved, data.ground_truth,
                              nees_options, &sh, &error));
    position += s.position.mean / kSeeds;
    pose += s.pose.mean / kSeeds;
    bias += s.bias.mean / kSeeds;
    pose_double += s2.pose.mean / kSeeds;
    pose_half += sh.pose.mean / kSeeds;
    bias_double += s2.bias.mean / kSeeds;
    bias_half += sh.bias.mean / kSeeds;
  }
  std::printf(
      "mean NEES over %d seeds: position %.2f (3), pose %.2f (6), bias %.2f "
      "(6); covariance x2: pose %.2f bias %.2f, x0.5: pose %.2f bias %.2f\n",
      kSeeds, position, pose, bias, pose_double, bias_double, pose_half,
      bias_half);
  const double kFactor = 1.4;
  EXPECT_GT(position, 3.0 / kFactor);
  EXPECT_LT(position, 3.0 * kFactor);
  EXPECT_GT(pose, 6.0 / kFactor);
  EXPECT_LT(pose, 6.0 * kFactor);
  EXPECT_GT(bias, 6.0 / kFactor);
  EXPECT_LT(bias, 6.0 * kFactor);
  // The bounds catch a covariance off by a factor 2 either way.
  EXPECT_LT(pose_double, 6.0 / kFactor);
  EXPECT_GT(pose_half, 6.0 * kFactor);
  EXPECT_LT(bias_double, 6.0 / kFactor);
  EXPECT_GT(bias_half, 6.0 * kFactor);
}

std::vector<InertialGroundTruth> Reference() {
  std::vector<InertialGroundTruth> ref;
  for (int i = 0; i < 50; ++i) {
    InertialGroundTruth g;
    g.stamp = i * 50000000ll;  // 20 Hz
    const double s = 0.05 * i;
    g.pose = Pose3(Eigen::Vector3d(std::cos(s), std::sin(s), 0.1 * s),
                   Eigen::Quaterniond(Eigen::AngleAxisd(
                       s, Eigen::Vector3d(0.1, 0.2, 1.0).normalized())));
    g.velocity = Eigen::Vector3d(-std::sin(s), std::cos(s), 0.1);
    g.bias.setConstant(0.01 * i);
    ref.push_back(g);
  }
  return ref;
}

TEST(InertialNeesTest, InterpolatesGroundTruth) {
  const std::vector<InertialGroundTruth> ref = Reference();
  InertialGroundTruth g;
  ASSERT_TRUE(InterpolateGroundTruth(ref, 25000000, 100000000, &g));
  EXPECT_NEAR((g.pose.t - 0.5 * (ref[0].pose.t + ref[1].pose.t)).norm(), 0.0,
              1e-12);
  EXPECT_NEAR(g.bias[3], 0.005, 1e-12);
  EXPECT_NEAR(g.pose.q.angularDistance(ref[0].pose.q),
              g.pose.q.angularDistance(ref[1].pose.q), 1e-12);
  ASSERT_TRUE(InterpolateGroundTruth(ref, 100000000, 1, &g));  // Exact stamp.
  EXPECT_EQ(g.pose.t, ref[2].pose.t);
  EXPECT_FALSE(InterpolateGroundTruth(ref, -1, 100000000, &g));
  EXPECT_FALSE(
      InterpolateGroundTruth(ref, ref.back().stamp + 1, 100000000, &g));
  EXPECT_FALSE(InterpolateGroundTruth(ref, 25000000, 40000000, &g));  // Gap.
}

TEST(InertialNeesTest, YawOffsetOfTheReferenceIsRecognisedAndRemoved) {
  const std::vector<InertialGroundTruth> ref = Reference();
  const double yaw = 1.3 * M_PI / 180.0;
  const Eigen::Quaterniond rz(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  // Estimates: the reference rotated by the yaw (positions exact), each with
  // a small covariance.
  std::vector<InertialState> states;
  std::vector<Eigen::MatrixXd> covs;
  for (const InertialGroundTruth& g : ref) {
    InertialState x;
    x.stamp = g.stamp;
    x.state.pose = Pose3(g.pose.t, rz * g.pose.q);
    x.state.velocity = g.velocity;
    x.bias = g.bias;
    states.push_back(x);
    covs.push_back(Eigen::MatrixXd::Identity(15, 15) * 1e-6);
  }
  NeesOptions options;
  options.skip_seconds = 0.5;
  EXPECT_NEAR(EstimateYawOffset(states, ref, options), yaw, 1e-9);
  NeesSummary raw, aligned;
  std::string error;
  ASSERT_TRUE(SummarizeNees(states, covs, ref, options, &raw, &error)) << error;
  EXPECT_EQ(raw.keyframes, 40);  // 50 minus the first 0.5 s.
  EXPECT_GT(raw.pose.mean, 100.0);
  // Every estimate is off by the yaw about the world's z: a body-frame
  // rotation error of the same angle.
  EXPECT_NEAR(raw.rotation_rmse, yaw, 1e-9);
  options.yaw_offset = yaw;
  ASSERT_TRUE(SummarizeNees(states, covs, ref, options, &aligned, &error));
  EXPECT_LT(aligned.pose.mean, 1e-12);
  EXPECT_LT(aligned.rotation_rmse, 1e-9);
  EXPECT_LT(aligned.position.mean, 1e-12);
  // Mismatched sizes and nothing to evaluate are errors.
  covs.pop_back();
  EXPECT_FALSE(SummarizeNees(states, covs, ref, options, &raw, &error));
  covs.push_back(covs.back());
  options.skip_seconds = 100.0;
  EXPECT_FALSE(SummarizeNees(states, covs, ref, options, &raw, &error));
}

TEST(InertialNeesTest, CovarianceCsvRoundTrip) {
  TestRng rng(3);
  std::vector<InertialState> states(3);
  std::vector<Eigen::MatrixXd> covs;
  for (int k = 0; k < 3; ++k) {
    states[k].stamp = 1403715273262142976ll + k * 100000000ll;
    const Eigen::MatrixXd c = rng.SpdMatrix(15, 1e-3 * (k + 1));
    covs.push_back(0.5 * (c + c.transpose()));  // Exactly symmetric.
  }
  const std::string text = CovarianceCsv(states, covs);
  // Header: stamp + 120 named columns with units.
  const std::string header = text.substr(0, text.find('\n'));
  EXPECT_EQ(
      header.rfind("#timestamp [ns],cov(px,px) [m*m],cov(px,py) [m*m]", 0), 0u)
      << header.substr(0, 80);
  EXPECT_NE(header.find(",cov(px,thz) [m*rad],"), std::string::npos);
  EXPECT_NE(header.find(",cov(baz,baz) [m/s^2*m/s^2]"), std::string::npos);
  std::vector<TimeNs> stamps;
  std::vector<Eigen::MatrixXd> back;
  std::string error;
  ASSERT_TRUE(ParseCovarianceCsv(text, &stamps, &back, &error)) << error;
  ASSERT_EQ(back.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(stamps[k], states[k].stamp);
    EXPECT_EQ(back[k], covs[k]);  // Bit for bit (shortest round-trip).
  }
  // Bad text: names the line.
  EXPECT_FALSE(ParseCovarianceCsv(text + "12,1,2\n", &stamps, &back, &error));
  EXPECT_NE(error.find("line 5: expected 121 fields, found 3"),
            std::string::npos)
      << error;
  std::string bad = text;
  bad.replace(bad.rfind(',') + 1, 1, "x");
  EXPECT_FALSE(ParseCovarianceCsv(bad, &stamps, &back, &error));
  EXPECT_NE(error.find("line 4: bad number"), std::string::npos) << error;
}

TEST(InertialBiasSettingsTest, InitialBiasKeysAreReadDumpedAndUsed) {
  const std::string dir = TempDir();
  WriteText(dir + "/c.yaml",
            "inertial:\n  initial_gyro_bias: [0.001, -0.002, 0.003]\n"
            "  initial_accel_bias: [0.1, 0.2, -0.3]\n"
            "  prior_gyro_bias_sigma: 1e-6\n"
            "  prior_accel_bias_sigma: 1e-6\n");
  InertialConfig config;
  std::string error;
  ASSERT_TRUE(LoadInertialConfig(dir + "/c.yaml", &config, &error)) << error;
  ImuBias expected;
  expected << 0.001, -0.002, 0.003, 0.1, 0.2, -0.3;
  EXPECT_EQ(config.options.initial_bias, expected);
  // --dump_config text loads back to the same settings.
  WriteText(dir + "/dump.yaml", InertialConfigToYaml(config));
  InertialConfig again;
  ASSERT_TRUE(LoadInertialConfig(dir + "/dump.yaml", &again, &error)) << error;
  EXPECT_EQ(again.options.initial_bias, expected);
  // Wrong length: an error naming the file and key.
  WriteText(dir + "/bad.yaml", "inertial:\n  initial_accel_bias: [1, 2]\n");
  EXPECT_FALSE(LoadInertialConfig(dir + "/bad.yaml", &again, &error));
  EXPECT_NE(error.find("bad.yaml: inertial.initial_accel_bias must be a list "
                       "of 3 numbers"),
            std::string::npos)
      << error;
  // Used as the first keyframe's bias prior: with a tight prior the first
  // estimate holds it.
  InertialOptions options = config.options;
  options.newest_covariance = false;
  InertialData data = Simulate(5, options);
  InertialRun run;
  ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error)) << error;
  EXPECT_LT((run.filter.front().bias - expected).norm(), 1e-5)
      << run.filter.front().bias.transpose();
}

// The failure mode the noise inflation settings fix: readings noisier than
// the data sheet (simulated with the gyro / accel white noise 16 / 8 times
// the data sheet density, random walks as the data sheet). Estimated with
// the data sheet densities the newest state is overconfident; with the
// inflation settings (config keys, EffectiveInertialOptions) it is
// consistent.
TEST(InertialNoiseInflationTest, InflationKeysRestoreConsistencyOnNoisierData) {
  const std::string dir = TempDir();
  WriteText(dir + "/c.yaml",
            "inertial:\n  gyro_noise_inflation: 16\n"
            "  accel_noise_inflation: 8\n");
  InertialConfig config;
  std::string error;
  ASSERT_TRUE(LoadInertialConfig(dir + "/c.yaml", &config, &error)) << error;
  const InertialOptions sheet = config.options;  // Densities not touched.
  const InertialOptions inflated = EffectiveInertialOptions(config);
  EXPECT_EQ(inflated.noise.gyro_noise_density,
            16.0 * sheet.noise.gyro_noise_density);
  EXPECT_EQ(inflated.noise.accel_noise_density,
            8.0 * sheet.noise.accel_noise_density);
  EXPECT_EQ(inflated.noise.gyro_random_walk, sheet.noise.gyro_random_walk);
  EXPECT_EQ(inflated.noise.accel_random_walk, sheet.noise.accel_random_walk);
  WriteText(dir + "/dump.yaml", InertialConfigToYaml(config));
  InertialConfig again;
  ASSERT_TRUE(LoadInertialConfig(dir + "/dump.yaml", &again, &error)) << error;
  EXPECT_EQ(again.gyro_noise_inflation, 16.0);
  EXPECT_EQ(again.accel_noise_inflation, 8.0);
  WriteText(dir + "/bad.yaml", "inertial:\n  accel_noise_inflation: 0\n");
  EXPECT_FALSE(LoadInertialConfig(dir + "/bad.yaml", &again, &error));
  EXPECT_NE(error.find("noise inflations must be > 0"), std::string::npos)
      << error;

  NeesOptions nees_options;
  nees_options.skip_seconds = 5.0;
  constexpr int kSeeds = 6;
  double pose_sheet = 0.0, pose_inflated = 0.0, position_inflated = 0.0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    InertialOptions sim_options = inflated;
    sim_options.newest_covariance = true;
    const InertialData data =
        testing::SimulateConsistentStart(300 + seed, 20.0, 2.0, sim_options);
    for (bool inflate : {false, true}) {
      InertialOptions options = inflate ? inflated : sheet;
      options.newest_covariance = true;
      InertialRun run;
      ASSERT_TRUE(RunSlidingWindow(data, options, &run, nullptr, &error))
          << error;
      NeesSummary s;
      ASSERT_TRUE(SummarizeNees(run.filter, run.newest_covariance,
                                data.ground_truth, nees_options, &s, &error))
          << error;
      (inflate ? pose_inflated : pose_sheet) += s.pose.mean / kSeeds;
      if (inflate) position_inflated += s.position.mean / kSeeds;
    }
  }
  std::printf(
      "noisier data: pose NEES %.2f with the data sheet densities, %.2f "
      "(position %.2f) with the inflation\n",
      pose_sheet, pose_inflated, position_inflated);
  EXPECT_GT(pose_sheet, 6.0 * 1.4);  // Outside the consistency bound.
  EXPECT_GT(pose_inflated, 6.0 / 1.4);
  EXPECT_LT(pose_inflated, 6.0 * 1.4);
  EXPECT_GT(position_inflated, 3.0 / 1.4);
  EXPECT_LT(position_inflated, 3.0 * 1.4);
}

}  // namespace
}  // namespace slam
