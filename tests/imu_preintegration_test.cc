// Tests of the IMU preintegration (core/imu_preintegration.h) and the
// inertial factors (factors/inertial_factors.h and the functors behind it):
//   * noise-free readings of an analytic trajectory reproduce the relative
//     motion (R, v, p) between two times, with the second-order convergence
//     of the midpoint scheme; to numerical precision for a spline made of
//     the pieces the scheme represents exactly;
//   * the propagated covariance matches Monte-Carlo samples;
//   * the bias Jacobians match re-integration with a perturbed bias;
//   * Jacobians of every inertial factor against numeric differentiation
//     (ceres::GradientChecker with the SE(3) manifold on poses);
//   * the builders' whitening (|r|^2 = e^T Omega e) and rejection of bad input.
#include "core/imu_preintegration.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ceres/gradient_checker.h"
#include "core/graph.h"
#include "core/lie.h"
#include "core/manifolds.h"
#include "core/marginals.h"
#include "core/optimizer.h"
#include "datasets/inertial_simulator.h"
#include "datasets/inertial_trajectory.h"
#include "factors/imu_factor.h"
#include "factors/inertial_factors.h"
#include "factors/pose_factors.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Rng = ::slam::testing::TestRng;

// Readings of the trajectory at time t (noise-free), with a constant bias.
void TrueReadings(const LissajousTrajectory& traj, double t,
                  const Eigen::Vector3d& gravity, const ImuBias& bias,
                  Eigen::Vector3d* accel, Eigen::Vector3d* gyro) {
  const TrajectorySample s = traj.Evaluate(t);
  *accel = s.pose.q.conjugate() * (s.acceleration - gravity) + bias.tail<3>();
  *gyro = s.omega + bias.head<3>();
}

// Integrates [t0, t0 + duration] at `rate` Hz with readings taken at the
// middle of every interval.
PreintegratedImu IntegrateTrajectory(const LissajousTrajectory& traj, double t0,
                                     double duration, double rate,
                                     const ImuBias& true_bias,
                                     const ImuBias& bias_lin) {
  PreintegratedImu pim(ImuNoise(), bias_lin);
  const int n = static_cast<int>(std::lround(duration * rate));
  const double dt = duration / n;
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3d a, g;
    TrueReadings(traj, t0 + (k + 0.5) * dt, pim.gravity(), true_bias, &a, &g);
    EXPECT_TRUE(pim.Integrate(a, g, dt));
  }
  return pim;
}

NavState StateAt(const LissajousTrajectory& traj, double t) {
  const TrajectorySample s = traj.Evaluate(t);
  NavState state;
  state.pose = s.pose;
  state.velocity = s.velocity;
  return state;
}

struct MotionError {
  double rotation = 0.0;  // rad
  double velocity = 0.0;  // m/s
  double position = 0.0;  // m
};

MotionError PredictionError(const LissajousTrajectory& traj, double t0,
                            double duration, double rate, const ImuBias& bias) {
  const PreintegratedImu pim =
      IntegrateTrajectory(traj, t0, duration, rate, bias, bias);
  const NavState predicted = pim.Predict(StateAt(traj, t0), bias);
  const NavState truth = StateAt(traj, t0 + duration);
  MotionError e;
  e.rotation =
      QuaternionLog<double>(truth.pose.q.conjugate() * predicted.pose.q).norm();
  e.velocity = (truth.velocity - predicted.velocity).norm();
  e.position = (truth.pose.t - predicted.pose.t).norm();
  return e;
}

TEST(ImuPreintegrationTest, ConstantReadings) {
  // Constant body rate w and specific force a: R(t) = Exp(w t) exactly (the
  // midpoint scheme is exact in rotation for a constant rate); velocity and
  // position against a fine integration (200 Hz against 20 kHz).
  const Eigen::Vector3d accel(0.3, -0.2, 9.9), gyro(0.4, -0.3, 0.8);
  PreintegratedImu coarse, fine;
  for (int k = 0; k < 200; ++k) coarse.Integrate(accel, gyro, 0.005);
  for (int k = 0; k < 20000; ++k) fine.Integrate(accel, gyro, 0.00005);
  EXPECT_NEAR(coarse.delta_t(), 1.0, 1e-12);
  EXPECT_LT(QuaternionLog<double>(coarse.delta_q().conjugate() *
                                  QuaternionExp<double>(gyro))
                .norm(),
            1e-12);
  EXPECT_LT((coarse.delta_v() - fine.delta_v()).norm(), 2e-5);
  EXPECT_LT((coarse.delta_p() - fine.delta_p()).norm(), 1e-5);
}

TEST(ImuPreintegrationTest, NoiseFreeReadingsReproduceRelativeMotion) {
  const LissajousTrajectory traj;
  ImuBias bias;
  bias << 0.01, -0.02, 0.015, 0.1, -0.05, 0.08;
  // 1 s at 200 Hz, readings at the interval midpoints. Measured: rotation
  // 1.9e-7 rad, velocity 3.8e-6 m/s, position 2.3e-6 m. The velocity error
  // is the rotation error times g (the gravity the accelerometer senses is
  // rotated with the integrated attitude), so the bounds are 1e-6 rad and
  // 1e-5 m/s, m; the brief's 1e-6 holds for the rotation only.
  const MotionError e200 = PredictionError(traj, 2.0, 1.0, 200.0, bias);
  EXPECT_LT(e200.rotation, 1e-6);
  EXPECT_LT(e200.velocity, 1e-5);
  EXPECT_LT(e200.position, 1e-5);
  // Second order: doubling the rate divides the error by about four.
  const MotionError e400 = PredictionError(traj, 2.0, 1.0, 400.0, bias);
  EXPECT_NEAR(e200.rotation / e400.rotation, 4.0, 0.4);
  EXPECT_NEAR(e200.velocity / e400.velocity, 4.0, 0.4);
  EXPECT_NEAR(e200.position / e400.position, 4.0, 0.4);
  // 3 s (measured 3.8e-7 rad, 6.3e-6 m/s, 1.5e-5 m).
  const MotionError e3 = PredictionError(traj, 5.0, 3.0, 200.0, bias);
  EXPECT_LT(e3.rotation, 1e-6);
  EXPECT_LT(e3.velocity, 2e-5);
  EXPECT_LT(e3.position, 5e-5);
  // The factor error of the true states is that integration error.
  const PreintegratedImu pim =
      IntegrateTrajectory(traj, 2.0, 1.0, 200.0, bias, bias);
  EXPECT_LT(pim.Error(StateAt(traj, 2.0), bias, StateAt(traj, 3.0)).norm(),
            1e-5);
}

// Noise-free readings of a trajectory that the discrete model represents
// exactly reproduce the relative motion to numerical precision. The
// trajectory is a spline whose pieces are the motions the midpoint scheme
// integrates without discretization error: on every IMU interval
// [t_k, t_k + dt] the body rate w_k is constant (rotation: a geodesic,
// degree-1 spline on SO(3), R(t) = R_k Exp(w_k (t - t_k))) and the world
// acceleration A_k is constant (position: a C1 quadratic spline). The
// accelerometer's specific force R(t)^T (A_k - g) varies within the interval;
// its value at the middle, which the scheme is documented to take, is what
// the IMU reports. Rates and accelerations change from piece to piece
// (smooth sines), the bias is non-zero, and the states are propagated in the
// world frame independently of the preintegration's body-frame algebra
// (gravity, bias, frame of i). Smooth motion (NoiseFreeReadingsReproduce-
// RelativeMotion) adds the scheme's O(dt^2) discretization error.
TEST(ImuPreintegrationTest, ExactForMotionTheSchemeRepresents) {
  ImuBias bias;
  bias << 0.01, -0.02, 0.015, 0.1, -0.05, 0.08;
  const Eigen::Vector3d gravity(0.0, 0.0, -9.81);
  const double dt = 0.005;
  const int n = 400;  // 2 s at 200 Hz.
  NavState truth;
  truth.pose.q = QuaternionExp<double>(Eigen::Vector3d(0.3, -0.2, 1.1));
  truth.pose.t = Eigen::Vector3d(4.0, -2.0, 1.5);
  truth.velocity = Eigen::Vector3d(1.2, 0.4, -0.3);
  const NavState start = truth;
  PreintegratedImu pim(ImuNoise(), bias, gravity);
  for (int k = 0; k < n; ++k) {
    const double t = k * dt;
    const Eigen::Vector3d w(0.8 * std::sin(1.3 * t), 0.5 * std::cos(0.7 * t),
                            1.1 * std::sin(0.9 * t + 0.4));
    const Eigen::Vector3d acc(2.0 * std::cos(1.1 * t), -1.5 * std::sin(0.8 * t),
                              0.7 * std::sin(2.1 * t));
    const Eigen::Quaterniond q_mid =
        truth.pose.q * QuaternionExp<double>(Eigen::Vector3d(0.5 * dt * w));
    const Eigen::Vector3d accel_reading =
        q_mid.conjugate() * (acc - gravity) + bias.tail<3>();
    const Eigen::Vector3d gyro_reading = w + bias.head<3>();
    ASSERT_TRUE(pim.Integrate(accel_reading, gyro_reading, dt));
    // The spline piece, in the world frame.
    truth.pose.t += truth.velocity * dt + 0.5 * acc * dt * dt;
    truth.velocity += acc * dt;
    truth.pose.q =
        (truth.pose.q * QuaternionExp<double>(Eigen::Vector3d(w * dt)))
            .normalized();
  }
  const NavState predicted = pim.Predict(start, bias);
  // Numerical precision: 400 steps of double arithmetic on values of order
  // 1-10 (measured ~1e-14 rad, ~1e-13 m/s and m).
  EXPECT_LT(
      QuaternionLog<double>(truth.pose.q.conjugate() * predicted.pose.q).norm(),
      1e-12);
  EXPECT_LT((truth.velocity - predicted.velocity).norm(), 1e-11);
  EXPECT_LT((truth.pose.t - predicted.pose.t).norm(), 1e-11);
  EXPECT_LT(pim.Error(start, bias, truth).norm(), 1e-11);
}

TEST(ImuPreintegrationTest, IntegratesStampedSamplesBetweenKeyframes) {
  // Readings sampled at 200 Hz stamps (as an IMU delivers them), keyframes
  // between samples: IntegrateImuSamples interpolates and stays second
  // order (measured ~4e-6 m/s, 3e-6 m over 1 s).
  const LissajousTrajectory traj;
  ImuBias bias;
  bias << -0.01, 0.02, 0.005, -0.1, 0.05, 0.2;
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 1000; ++k) {
    ImuSample s;
    s.stamp = SecondsToNs(k * 0.005);
    TrueReadings(traj, NsToSeconds(s.stamp), DefaultGravity(), bias, &s.accel,
                 &s.gyro);
    samples.push_back(s);
  }
  const TimeNs t0 = SecondsToNs(1.2345), t1 = SecondsToNs(2.2345);
  PreintegratedImu pim(ImuNoise(), bias);
  ASSERT_TRUE(IntegrateImuSamples(samples, t0, t1, &pim));
  EXPECT_NEAR(pim.delta_t(), 1.0, 1e-12);
  EXPECT_EQ(pim.num_samples(), 201);  // 200 stamps inside: 201 pieces.
  const NavState predicted = pim.Predict(StateAt(traj, NsToSeconds(t0)), bias);
  const NavState truth = StateAt(traj, NsToSeconds(t1));
  EXPECT_LT(
      QuaternionLog<double>(truth.pose.q.conjugate() * predicted.pose.q).norm(),
      1e-6);
  EXPECT_LT((truth.velocity - predicted.velocity).norm(), 1e-5);
  EXPECT_LT((truth.pose.t - predicted.pose.t).norm(), 1e-5);
  // Bad calls leave the preintegration untouched.
  EXPECT_FALSE(IntegrateImuSamples(samples, t1, t0, &pim));
  EXPECT_FALSE(IntegrateImuSamples({}, t0, t1, &pim));
  EXPECT_EQ(pim.num_samples(), 201);
}

TEST(ImuPreintegrationTest, HoldInterpolationHoldsEachSample) {
  std::vector<ImuSample> samples(2);
  samples[0].stamp = 0;
  samples[0].accel = Eigen::Vector3d(0.1, 0.2, 9.8);
  samples[0].gyro = Eigen::Vector3d(0.3, -0.1, 0.2);
  samples[1].stamp = 10000000;
  samples[1].accel = Eigen::Vector3d(-0.4, 0.5, 9.7);
  samples[1].gyro = Eigen::Vector3d(-0.2, 0.4, 0.1);
  // [2 ms, 25 ms]: sample 0 over 8 ms, sample 1 over 15 ms.
  PreintegratedImu held, expected, linear;
  ASSERT_TRUE(IntegrateImuSamples(samples, 2000000, 25000000, &held,
                                  ImuInterpolation::kHold));
  expected.Integrate(samples[0].accel, samples[0].gyro, 0.008);
  expected.Integrate(samples[1].accel, samples[1].gyro, 0.015);
  EXPECT_LT((held.delta_p() - expected.delta_p()).norm(), 1e-15);
  EXPECT_LT((held.delta_v() - expected.delta_v()).norm(), 1e-15);
  EXPECT_LT((held.covariance() - expected.covariance()).norm(), 1e-15);
  ASSERT_TRUE(IntegrateImuSamples(samples, 2000000, 25000000, &linear));
  EXPECT_GT((linear.delta_v() - expected.delta_v()).norm(), 1e-4);
}

TEST(ImuPreintegrationTest, RejectsBadSamples) {
  PreintegratedImu pim;
  const Eigen::Vector3d a(0, 0, 9.81), g(0.1, 0, 0);
  EXPECT_FALSE(pim.Integrate(a, g, 0.0));
  EXPECT_FALSE(pim.Integrate(a, g, -0.01));
  EXPECT_FALSE(pim.Integrate(a, g, std::nan("")));
  EXPECT_FALSE(pim.Integrate(Eigen::Vector3d(NAN, 0, 0), g, 0.01));
  EXPECT_EQ(pim.num_samples(), 0);
  EXPECT_TRUE(pim.Integrate(a, g, 0.01));
  EXPECT_EQ(pim.num_samples(), 1);
}

// One reading (keyframes at the IMU rate) or two: the covariance is that of
// continuous white noise integrated over dt (position variance
// sigma_a^2 dt^3 / 3, velocity-position covariance sigma_a^2 dt^2 / 2), so
// positive definite, and the IMU factor can be built. Held readings alone
// gave dt^3 / 4 and a rank-6 covariance ("not positive definite").
TEST(ImuPreintegrationTest, OneOrTwoReadingsGiveAPositiveDefiniteCovariance) {
  const ImuNoise noise;
  const double dt = 0.005;
  PreintegratedImu still(noise);
  ASSERT_TRUE(
      still.Integrate(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), dt));
  const double var_a = noise.accel_noise_density * noise.accel_noise_density;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(still.covariance()(6 + i, 6 + i), var_a * dt * dt * dt / 3.0,
                1e-12 * var_a * dt * dt * dt);
    EXPECT_NEAR(still.covariance()(3 + i, 6 + i), var_a * dt * dt / 2.0,
                1e-12 * var_a * dt * dt);
  }
  const LissajousTrajectory traj;
  for (int n : {1, 2}) {
    PreintegratedImu pim(noise);
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d a, g;
      TrueReadings(traj, 2.0 + (k + 0.5) * dt, DefaultGravity(),
                   ImuBias::Zero(), &a, &g);
      ASSERT_TRUE(pim.Integrate(a, g, dt));
    }
    Eigen::LLT<Eigen::MatrixXd> llt(pim.covariance());
    EXPECT_EQ(llt.info(), Eigen::Success) << n << " readings";
    Factor f;
    std::string error;
    EXPECT_TRUE(MakeImuFactor(Pose3Key(0), VelocityKey(0), ImuBiasKey(0),
                              Pose3Key(1), VelocityKey(1), pim, &f, &error))
        << n << " readings: " << error;
  }
}

// Error of a noisy integration against the nominal one, in the covariance's
// order [dphi, dv, dp] with the right perturbation.
ImuVector9 Deviation(const PreintegratedImu& nominal,
                     const PreintegratedImu& noisy) {
  ImuVector9 d;
  d.segment<3>(0) =
      QuaternionLog<double>(nominal.delta_q().conjugate() * noisy.delta_q());
  d.segment<3>(3) = noisy.delta_v() - nominal.delta_v();
  d.segment<3>(6) = noisy.delta_p() - nominal.delta_p();
  return d;
}

// Monte Carlo of the preintegrated deltas over 1 s at 200 Hz: white noise
// at the given densities and, with `drift`, the bias as a random walk from
// b_i = 0 (the reading of step k carries beta_k, beta_0 = 0). Compares the
// sample covariance with covariance() and returns the latter.
ImuMatrix9 ExpectCovarianceMatchesMonteCarlo(const ImuNoise& noise,
                                             bool drift) {
  const LissajousTrajectory traj;
  const double rate = 200.0, t0 = 1.0;
  const int n = 200;
  const double dt = 1.0 / rate;
  std::vector<Eigen::Vector3d> accel(n), gyro(n);
  for (int k = 0; k < n; ++k) {
    TrueReadings(traj, t0 + (k + 0.5) * dt, DefaultGravity(), ImuBias::Zero(),
                 &accel[k], &gyro[k]);
  }
  PreintegratedImu nominal(noise);
  for (int k = 0; k < n; ++k) nominal.Integrate(accel[k], gyro[k], dt);

  Rng rng(7);
  const int kRuns = 2000;
  const double sg = noise.gyro_noise_density / std::sqrt(dt);
  const double sa = noise.accel_noise_density / std::sqrt(dt);
  const double wg = noise.gyro_random_walk * std::sqrt(dt);
  const double wa = noise.accel_random_walk * std::sqrt(dt);
  ImuMatrix9 sample = ImuMatrix9::Zero();
  ImuVector9 mean = ImuVector9::Zero();
  std::vector<ImuVector9> deviations;
  for (int run = 0; run < kRuns; ++run) {
    PreintegratedImu noisy(noise);
    Eigen::Vector3d beta_g = Eigen::Vector3d::Zero();
    Eigen::Vector3d beta_a = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) {
      noisy.Integrate(accel[k] + beta_a + sa * rng.Normal3(),
                      gyro[k] + beta_g + sg * rng.Normal3(), dt);
      if (drift) {
        beta_g += wg * rng.Normal3();
        beta_a += wa * rng.Normal3();
      }
    }
    deviations.push_back(Deviation(nominal, noisy));
    mean += deviations.back();
  }
  mean /= kRuns;
  for (const ImuVector9& d : deviations) {
    sample += (d - mean) * (d - mean).transpose();
  }
  sample /= (kRuns - 1);
  const ImuMatrix9& p = nominal.covariance();
  // The standard deviation of a sample covariance entry is
  // sqrt((P_ii P_jj + P_ij^2) / N); allow 5 of them (81 entries).
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) {
      const double sd =
          std::sqrt((p(i, i) * p(j, j) + p(i, j) * p(i, j)) / kRuns);
      EXPECT_NEAR(sample(i, j), p(i, j), 5.0 * sd)
          << "entry (" << i << ", " << j << ")";
    }
    // Diagonal within 15 % (its relative sd is sqrt(2 / N) = 3 %).
    EXPECT_NEAR(sample(i, i) / p(i, i), 1.0, 0.15) << "diagonal " << i;
  }
  return p;
}

TEST(ImuPreintegrationTest, CovarianceMatchesMonteCarlo) {
  ImuNoise noise;  // ADIS16448, inflated x10 so that nonlinearity shows.
  noise.gyro_noise_density *= 10.0;
  noise.accel_noise_density *= 10.0;
  noise.gyro_random_walk = 1e-12;  // White noise only.
  noise.accel_random_walk = 1e-12;
  const ImuMatrix9 p = ExpectCovarianceMatchesMonteCarlo(noise, false);
  // Not a trivial match: the covariance is far from diagonal (rotation
  // noise drives velocity and position) and grows from zero.
  double max_rv_correlation = 0.0;
  for (int i = 3; i < 6; ++i) {
    for (int j = 0; j < 3; ++j) {
      max_rv_correlation = std::max(
          max_rv_correlation, std::abs(p(i, j)) / std::sqrt(p(i, i) * p(j, j)));
    }
  }
  EXPECT_GT(max_rv_correlation, 0.3);
  EXPECT_GT(std::abs(p(6, 3)) / std::sqrt(p(3, 3) * p(6, 6)), 0.5);
}

// The bias drifts within the interval (random walk from b_i, which the
// factor holds fixed): covariance() includes that drift. Random walks
// inflated (x100) until they dominate the white noise, so that a covariance
// without them would fail the comparison.
TEST(ImuPreintegrationTest, CovarianceIncludesBiasDriftWithinTheInterval) {
  ImuNoise noise;
  noise.gyro_random_walk *= 100.0;
  noise.accel_random_walk *= 100.0;
  const ImuMatrix9 with_drift = ExpectCovarianceMatchesMonteCarlo(noise, true);
  ImuNoise white = noise;
  white.gyro_random_walk = 1e-12;
  white.accel_random_walk = 1e-12;
  PreintegratedImu without(white);
  const LissajousTrajectory traj;
  for (int k = 0; k < 200; ++k) {
    Eigen::Vector3d a, g;
    TrueReadings(traj, 1.0 + (k + 0.5) / 200.0, DefaultGravity(),
                 ImuBias::Zero(), &a, &g);
    without.Integrate(a, g, 1.0 / 200.0);
  }
  // The drift is most of the velocity and position uncertainty here.
  for (int i = 3; i < 9; ++i) {
    EXPECT_GT(with_drift(i, i), 2.0 * without.covariance()(i, i)) << i;
  }
}

TEST(ImuPreintegrationTest, BiasJacobiansMatchReintegration) {
  const LissajousTrajectory traj;
  ImuBias bias_lin;
  bias_lin << 0.02, -0.01, 0.03, 0.2, 0.1, -0.15;
  const ImuBias true_bias = ImuBias::Zero();
  const PreintegratedImu base =
      IntegrateTrajectory(traj, 3.0, 1.0, 200.0, true_bias, bias_lin);
  const double h = 1e-6;
  ImuMatrix96 numeric;
  for (int c = 0; c < 6; ++c) {
    ImuBias plus = bias_lin, minus = bias_lin;
    plus[c] += h;
    minus[c] -= h;
    const PreintegratedImu p =
        IntegrateTrajectory(traj, 3.0, 1.0, 200.0, true_bias, plus);
    const PreintegratedImu m =
        IntegrateTrajectory(traj, 3.0, 1.0, 200.0, true_bias, minus);
    numeric.col(c) = (Deviation(base, p) - Deviation(base, m)) / (2.0 * h);
  }
  const ImuMatrix96& analytic = base.bias_jacobian();
  EXPECT_LT((numeric - analytic).norm(), 1e-6 * analytic.norm())
      << "numeric\n"
      << numeric << "\nanalytic\n"
      << analytic;
  EXPECT_LT((analytic.block<3, 3>(0, 3).norm()), 1e-15);  // dR/dba = 0.

  // First-order correction of a finite bias change: the corrected deltas are
  // much closer to re-integration than the uncorrected ones.
  ImuBias db;
  db << 2e-3, -1e-3, 1.5e-3, 2e-2, -3e-2, 1e-2;
  const PreintegratedImu re =
      IntegrateTrajectory(traj, 3.0, 1.0, 200.0, true_bias, bias_lin + db);
  const ImuBias b = bias_lin + db;
  const double rot_err =
      QuaternionLog<double>(re.delta_q().conjugate() * base.CorrectedDeltaQ(b))
          .norm();
  const double rot_unc =
      QuaternionLog<double>(re.delta_q().conjugate() * base.delta_q()).norm();
  EXPECT_LT(rot_err, 1e-2 * rot_unc);
  EXPECT_LT((re.delta_v() - base.CorrectedDeltaV(b)).norm(),
            1e-2 * (re.delta_v() - base.delta_v()).norm());
  EXPECT_LT((re.delta_p() - base.CorrectedDeltaP(b)).norm(),
            1e-2 * (re.delta_p() - base.delta_p()).norm());
}

// ---------------------------------------------------------------------------
// Factors.

ceres::NumericDiffOptions NumericOptions() {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  return options;
}
constexpr double kGradientPrecision = 1e-7;
// No manifold: every parameter block Euclidean.
const std::vector<const ceres::Manifold*>* const kEuclidean = nullptr;

std::vector<double> PoseVector(const Pose3& p) { return Pose3Value(p); }

// Runs the gradient checker and compares every Jacobian block (in the
// tangent spaces) against the numeric one with a tolerance relative to the
// block's largest entry: ceres' per-entry relative error is meaningless for
// entries that are zero up to rounding (1e-13 against a numeric 1e-10 next
// to entries of 1e3), which the IMU factor has.
void ExpectJacobiansMatch(const ceres::CostFunction& cost,
                          const std::vector<const ceres::Manifold*>* manifolds,
                          const std::vector<const double*>& params) {
  ceres::GradientChecker checker(&cost, manifolds, NumericOptions());
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(params.data(), kGradientPrecision, &results);
  ASSERT_TRUE(results.return_value) << results.error_log;
  ASSERT_EQ(results.local_jacobians.size(), params.size());
  for (size_t b = 0; b < params.size(); ++b) {
    const Eigen::MatrixXd& analytic = results.local_jacobians[b];
    const Eigen::MatrixXd& numeric = results.local_numeric_jacobians[b];
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(),
              kGradientPrecision * scale)
        << "block " << b << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
  }
}

Eigen::VectorXd EvaluateCost(const Factor& f,
                             const std::vector<const double*>& params) {
  Eigen::VectorXd r(f.cost->num_residuals());
  EXPECT_TRUE(f.cost->Evaluate(params.data(), r.data(), nullptr));
  return r;
}

// Residuals and tangent-space Jacobians (ambient Jacobian times the
// manifold's PlusJacobian for 7-value pose blocks) of two cost functions.
void ExpectSameTangentJacobians(const ceres::CostFunction& a,
                                const ceres::CostFunction& b,
                                const std::vector<const double*>& params) {
  const int m = a.num_residuals();
  const std::vector<int32_t>& sizes = a.parameter_block_sizes();
  std::vector<Eigen::MatrixXd> ja, jb;
  std::vector<double*> pa, pb;
  for (int32_t size : sizes) {
    ja.emplace_back(m, size);
    jb.emplace_back(m, size);
  }
  for (size_t k = 0; k < sizes.size(); ++k) {
    pa.push_back(ja[k].data());
    pb.push_back(jb[k].data());
  }
  Eigen::VectorXd ra(m), rb(m);
  ASSERT_TRUE(a.Evaluate(params.data(), ra.data(), pa.data()));
  ASSERT_TRUE(b.Evaluate(params.data(), rb.data(), pb.data()));
  EXPECT_LT((ra - rb).norm(), 1e-12 * (1.0 + ra.norm()));
  const SE3Manifold se3;
  for (size_t k = 0; k < sizes.size(); ++k) {
    // The buffers are row-major m x size: transpose the column-major view.
    Eigen::MatrixXd a_k =
        Eigen::Map<Eigen::Matrix<double, -1, -1, Eigen::RowMajor>>(ja[k].data(),
                                                                   m, sizes[k]);
    Eigen::MatrixXd b_k =
        Eigen::Map<Eigen::Matrix<double, -1, -1, Eigen::RowMajor>>(jb[k].data(),
                                                                   m, sizes[k]);
    if (sizes[k] == 7) {
      Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
      se3.PlusJacobian(params[k], plus.data());
      a_k = a_k * plus;
      b_k = b_k * plus;
    }
    const double scale = std::max(1.0, b_k.cwiseAbs().maxCoeff());
    EXPECT_LT((a_k - b_k).cwiseAbs().maxCoeff(), 1e-9 * scale)
        << "block " << k << "\nanalytic\n"
        << a_k << "\nautodiff\n"
        << b_k;
  }
}

TEST(InertialFactorsTest, ImuFactorWhiteningAndJacobians) {
  const LissajousTrajectory traj;
  Rng rng(11);
  const SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3, nullptr, nullptr,
                                                         &se3, nullptr};
  for (int trial = 0; trial < 20; ++trial) {
    const double t0 = rng.Uniform(0.0, 20.0);
    ImuBias bias_lin;
    bias_lin << 0.01 * rng.Normal3(), 0.1 * rng.Normal3();
    const PreintegratedImu pim =
        IntegrateTrajectory(traj, t0, 0.5, 200.0, ImuBias::Zero(), bias_lin);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeImuFactor(Pose3Key(0), VelocityKey(0), ImuBiasKey(0),
                              Pose3Key(1), VelocityKey(1), pim, &f, &error))
        << error;
    EXPECT_EQ(f.type, FactorType::kImu);
    // The autodiff reference of the builder's analytic cost function.
    Eigen::MatrixXd sqrt_info;
    ASSERT_TRUE(SqrtInformationFromCovariance(pim.covariance(), &sqrt_info));
    const std::unique_ptr<ceres::CostFunction> autodiff(
        ImuFactor::Create(pim, sqrt_info));
    ASSERT_EQ(f.keys.size(), 5u);
    EXPECT_EQ(f.keys[2], ImuBiasKey(0));
    EXPECT_EQ(f.measurement.size(), 11);
    EXPECT_DOUBLE_EQ(f.measurement[10], pim.delta_t());
    // States near the truth, bias away from the linearization point.
    NavState si = StateAt(traj, t0), sj = StateAt(traj, t0 + 0.5);
    si.pose = si.pose * Pose3(0.1 * rng.Normal3(),
                              QuaternionExp<double>(0.05 * rng.Normal3()));
    sj.pose = sj.pose * Pose3(0.1 * rng.Normal3(),
                              QuaternionExp<double>(0.05 * rng.Normal3()));
    si.velocity += 0.1 * rng.Normal3();
    sj.velocity += 0.1 * rng.Normal3();
    ImuBias bias_i = bias_lin;
    bias_i += 0.01 * ImuBias::Random();
    const std::vector<double> xi = PoseVector(si.pose),
                              xj = PoseVector(sj.pose);
    const std::vector<const double*> params = {xi.data(), si.velocity.data(),
                                               bias_i.data(), xj.data(),
                                               sj.velocity.data()};
    // |r|^2 = e^T Sigma^-1 e with e the documented error.
    const ImuVector9 e = pim.Error(si, bias_i, sj);
    const Eigen::VectorXd r = EvaluateCost(f, params);
    const double expected = e.dot(pim.covariance().ldlt().solve(e));
    EXPECT_NEAR(r.squaredNorm(), expected, 1e-6 * expected);
    EXPECT_NEAR(r.squaredNorm(), e.dot(f.information * e), 1e-6 * expected);

    ExpectJacobiansMatch(*f.cost, &manifolds, params);
    ExpectSameTangentJacobians(*f.cost, *autodiff, params);
  }
}

TEST(InertialFactorsTest, RightJacobianInverse) {
  Rng rng(13);
  for (double scale : {1e-7, 1e-3, 0.5, 2.0, 3.0}) {
    const Eigen::Vector3d phi = scale * rng.UnitVector();
    EXPECT_LT((RightJacobianSO3(phi) * RightJacobianInverseSO3(phi) -
               Eigen::Matrix3d::Identity())
                  .norm(),
              1e-12)
        << scale;
  }
}

TEST(InertialFactorsTest, ImuErrorDefinition) {
  // Independent check of the error at a hand-built configuration: the states
  // at j predicted from i give e = 0 for any bias (the prediction uses the
  // same bias correction), and a rotation offset Exp(d) on R_j gives
  // r_R = d.
  const LissajousTrajectory traj;
  ImuBias bias;
  bias << 0.01, 0.02, -0.01, 0.1, 0.2, 0.3;
  const PreintegratedImu pim = IntegrateTrajectory(
      traj, 1.0, 1.0, 200.0, ImuBias::Zero(), ImuBias::Zero());
  const NavState si = StateAt(traj, 1.0);
  NavState sj = pim.Predict(si, bias);
  EXPECT_LT(pim.Error(si, bias, sj).norm(), 1e-12);
  const Eigen::Vector3d d(0.01, -0.02, 0.03);
  sj.pose.q = sj.pose.q * QuaternionExp<double>(d);
  sj.velocity += si.pose.q * Eigen::Vector3d(0.1, 0.2, 0.3);
  const ImuVector9 e = pim.Error(si, bias, sj);
  EXPECT_LT((e.head<3>() - d).norm(), 1e-12);
  EXPECT_LT((e.segment<3>(3) - Eigen::Vector3d(0.1, 0.2, 0.3)).norm(), 1e-12);
  EXPECT_LT(e.tail<3>().norm(), 1e-12);
}

TEST(InertialFactorsTest, BiasRandomWalk) {
  ImuNoise noise;
  Factor f;
  std::string error;
  ASSERT_TRUE(
      MakeBiasRandomWalk(ImuBiasKey(0), ImuBiasKey(1), noise, 0.1, &f, &error));
  EXPECT_EQ(f.type, FactorType::kBiasRandomWalk);
  EXPECT_NEAR(f.information(0, 0),
              1.0 / (noise.gyro_random_walk * noise.gyro_random_walk * 0.1),
              1e-6 * f.information(0, 0));
  EXPECT_NEAR(f.information(5, 5),
              1.0 / (noise.accel_random_walk * noise.accel_random_walk * 0.1),
              1e-6 * f.information(5, 5));
  Rng rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    ImuBias bi, bj;
    bi << 1e-3 * rng.Normal3(), 1e-2 * rng.Normal3();
    bj << 1e-3 * rng.Normal3(), 1e-2 * rng.Normal3();
    const std::vector<const double*> params = {bi.data(), bj.data()};
    const ImuBias e = bj - bi;
    EXPECT_NEAR(EvaluateCost(f, params).squaredNorm(), e.dot(f.information * e),
                1e-9 * e.dot(f.information * e));
    ceres::GradientChecker checker(f.cost.get(), kEuclidean, NumericOptions());
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(params.data(), kGradientPrecision, &results))
        << results.error_log;
  }
  EXPECT_FALSE(
      MakeBiasRandomWalk(ImuBiasKey(0), ImuBiasKey(1), noise, 0.0, &f, &error));
  noise.gyro_random_walk = 0.0;
  EXPECT_FALSE(
      MakeBiasRandomWalk(ImuBiasKey(0), ImuBiasKey(1), noise, 0.1, &f, &error));
}

TEST(InertialFactorsTest, PositionFactorWithLeverArm) {
  Rng rng(5);
  const SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3};
  for (int trial = 0; trial < 20; ++trial) {
    const Pose3 x = rng.RandomPose3();
    const Eigen::Vector3d lever =
        trial == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(rng.Normal3());
    const Eigen::Vector3d z = x * lever + 0.5 * rng.Normal3();
    const Eigen::Matrix3d info = rng.ScaledInformation(3);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakePositionFactor(Pose3Key(2), z, info, lever, &f, &error));
    EXPECT_EQ(f.type, FactorType::kPosition);
    EXPECT_EQ(f.measurement.size(), 6);
    const std::vector<double> xv = Pose3Value(x);
    const std::vector<const double*> params = {xv.data()};
    // Independent: antenna position with a rotation matrix.
    const Eigen::Vector3d e = x.t + x.q.toRotationMatrix() * lever - z;
    EXPECT_NEAR(EvaluateCost(f, params).squaredNorm(), e.dot(info * e),
                1e-9 * e.dot(info * e));
    ceres::GradientChecker checker(f.cost.get(), &manifolds, NumericOptions());
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(params.data(), kGradientPrecision, &results))
        << results.error_log;
  }
  Factor f;
  std::string error;
  EXPECT_FALSE(MakePositionFactor(Pose3Key(0), Eigen::Vector3d::Zero(),
                                  -Eigen::Matrix3d::Identity(),
                                  Eigen::Vector3d::Zero(), &f, &error));
}

TEST(InertialFactorsTest, VelocityAndBiasPriors) {
  Rng rng(9);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d v = rng.Normal3(), zv = rng.Normal3();
    const Eigen::Matrix3d info_v = rng.ScaledInformation(3);
    Factor fv;
    std::string error;
    ASSERT_TRUE(MakePriorVelocity(VelocityKey(0), zv, info_v, &fv, &error));
    EXPECT_EQ(fv.type, FactorType::kPriorVelocity);
    const std::vector<const double*> pv = {v.data()};
    const Eigen::Vector3d ev = v - zv;
    EXPECT_NEAR(EvaluateCost(fv, pv).squaredNorm(), ev.dot(info_v * ev),
                1e-9 * ev.dot(info_v * ev));
    ceres::GradientChecker cv(fv.cost.get(), kEuclidean, NumericOptions());
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(cv.Probe(pv.data(), kGradientPrecision, &results))
        << results.error_log;

    ImuBias b, zb;
    b << rng.Normal3(), rng.Normal3();
    zb << rng.Normal3(), rng.Normal3();
    const Eigen::Matrix<double, 6, 6> info_b = rng.ScaledInformation(6);
    Factor fb;
    ASSERT_TRUE(MakePriorBias(ImuBiasKey(0), zb, info_b, &fb, &error));
    EXPECT_EQ(fb.type, FactorType::kPriorBias);
    const std::vector<const double*> pb = {b.data()};
    const ImuBias eb = b - zb;
    EXPECT_NEAR(EvaluateCost(fb, pb).squaredNorm(), eb.dot(info_b * eb),
                1e-9 * eb.dot(info_b * eb));
    ceres::GradientChecker cb(fb.cost.get(), kEuclidean, NumericOptions());
    EXPECT_TRUE(cb.Probe(pb.data(), kGradientPrecision, &results))
        << results.error_log;
  }
}

TEST(InertialFactorsTest, FactorsEnterTheGraph) {
  // The builders' factors are accepted by Graph::AddFactor with the node
  // kinds of core/keys.h, and an IMU factor between predicted states has
  // zero chi2.
  const LissajousTrajectory traj;
  const PreintegratedImu pim = IntegrateTrajectory(
      traj, 0.0, 0.2, 200.0, ImuBias::Zero(), ImuBias::Zero());
  const NavState s0 = StateAt(traj, 0.0);
  const NavState s1 = pim.Predict(s0, ImuBias::Zero());
  Graph graph;
  ASSERT_TRUE(AddInertialState(&graph, 0, 0, s0, ImuBias::Zero()));
  ImuBias b1;
  b1 << 1, 2, 3, 4, 5, 6;
  ASSERT_TRUE(AddInertialState(&graph, 1, 200000000, s1, b1));
  EXPECT_FALSE(AddInertialState(&graph, 1, 0, s1, b1));  // Exists.
  EXPECT_EQ(graph.NumNodes(), 6u);
  EXPECT_TRUE(graph.FindNode(VelocityKey(1))->has_stamp);
  EXPECT_EQ(graph.FindNode(ImuBiasKey(1))->stamp, 200000000);
  NavState back;
  ImuBias b_back;
  ASSERT_TRUE(GetInertialState(graph, 1, &back, &b_back));
  EXPECT_EQ(back.velocity, s1.velocity);
  EXPECT_EQ(b_back, b1);
  EXPECT_LT((back.pose.t - s1.pose.t).norm(), 1e-15);
  EXPECT_FALSE(GetInertialState(graph, 2, &back, &b_back));
  std::vector<double>& b1_value = graph.FindNode(ImuBiasKey(1))->value;
  std::fill(b1_value.begin(), b1_value.end(), 0.0);
  Factor imu, rw;
  std::string error;
  ASSERT_TRUE(MakeImuFactor(Pose3Key(0), VelocityKey(0), ImuBiasKey(0),
                            Pose3Key(1), VelocityKey(1), pim, &imu, &error));
  ASSERT_TRUE(MakeBiasRandomWalk(ImuBiasKey(0), ImuBiasKey(1), ImuNoise(), 0.2,
                                 &rw, &error));
  EXPECT_GE(graph.AddFactor(imu), 0);
  EXPECT_GE(graph.AddFactor(rw), 0);
  EXPECT_LT(graph.Chi2(), 1e-12);
  EXPECT_STREQ(FactorTypeName(FactorType::kImu), "imu");

  PreintegratedImu empty;
  EXPECT_FALSE(MakeImuFactor(Pose3Key(0), VelocityKey(0), ImuBiasKey(0),
                             Pose3Key(1), VelocityKey(1), empty, &imu, &error));
}

// End to end: a batch problem from simulated ADIS16448 data (IMU factors
// between keyframes every 0.5 s, bias random walks, 1 Hz position fixes with
// a lever arm, priors on the first state). The ground truth's chi2 follows
// the chi2 distribution of the residual count (the covariances are right),
// and the optimum recovers the trajectory and the biases.
TEST(InertialFactorsTest, BatchOnSimulatedDataIsConsistent) {
  InertialSimulationConfig config;
  config.duration = 30.0;
  config.position_rate = 1.0;
  config.position_sigma = 0.1;
  config.lever_arm = Eigen::Vector3d(0.2, 0.0, -0.1);
  InertialData data;
  std::string error;
  ASSERT_TRUE(SimulateInertial(config, &data, &error)) << error;
  const ImuNoise& noise = config.noise;
  const int per_keyframe = 100;  // 0.5 s at 200 Hz.
  const int num_keyframes =
      static_cast<int>(data.ground_truth.size() - 1) / per_keyframe + 1;
  Rng rng(21);
  Graph graph;
  for (int k = 0; k < num_keyframes; ++k) {
    const InertialGroundTruth& g = data.ground_truth[k * per_keyframe];
    const Pose3 perturbed =
        g.pose *
        Pose3(0.1 * rng.Normal3(), QuaternionExp<double>(0.02 * rng.Normal3()));
    const Eigen::Vector3d v = g.velocity + 0.1 * rng.Normal3();
    ASSERT_NE(graph.AddNode(Pose3Key(k), Pose3Value(perturbed)), nullptr);
    ASSERT_NE(graph.AddNode(VelocityKey(k), {v.x(), v.y(), v.z()}), nullptr);
    ASSERT_NE(graph.AddNode(ImuBiasKey(k), std::vector<double>(6, 0.0)),
              nullptr);
  }
  int residuals = 0;
  auto add = [&](const Factor& f) {
    ASSERT_GE(graph.AddFactor(f), 0);
    residuals += f.cost->num_residuals();
  };
  Factor f;
  // Priors on the first state around the truth (pose prior information is
  // over the quaternion vector part: 4 / sigma^2 for rotation).
  const InertialGroundTruth& g0 = data.ground_truth[0];
  Eigen::Matrix<double, 6, 1> pose_info;
  pose_info << 1e4, 1e4, 1e4, 4e4, 4e4, 4e4;  // 1 cm, 0.01 rad
  ASSERT_TRUE(
      MakePriorSE3(Pose3Key(0), g0.pose, pose_info.asDiagonal(), &f, &error));
  add(f);
  ASSERT_TRUE(MakePriorVelocity(VelocityKey(0), g0.velocity,
                                100.0 * Eigen::Matrix3d::Identity(), &f,
                                &error));
  add(f);
  Eigen::Matrix<double, 6, 1> bias_info;
  bias_info << 1e4, 1e4, 1e4, 100, 100, 100;  // 0.01 rad/s, 0.1 m/s^2
  ASSERT_TRUE(MakePriorBias(ImuBiasKey(0), ImuBias::Zero(),
                            bias_info.asDiagonal(), &f, &error));
  add(f);
  for (int k = 0; k + 1 < num_keyframes; ++k) {
    const TimeNs ti = data.ground_truth[k * per_keyframe].stamp;
    const TimeNs tj = data.ground_truth[(k + 1) * per_keyframe].stamp;
    PreintegratedImu pim(noise, ImuBias::Zero(), data.gravity);
    ASSERT_TRUE(IntegrateImuSamples(data.imu, ti, tj, &pim));
    ASSERT_TRUE(MakeImuFactor(Pose3Key(k), VelocityKey(k), ImuBiasKey(k),
                              Pose3Key(k + 1), VelocityKey(k + 1), pim, &f,
                              &error));
    add(f);
    ASSERT_TRUE(MakeBiasRandomWalk(ImuBiasKey(k), ImuBiasKey(k + 1), noise,
                                   NsToSeconds(tj - ti), &f, &error));
    add(f);
  }
  for (const PositionFix& fix : data.positions) {
    const int k = static_cast<int>(fix.stamp / (per_keyframe * 5000000LL));
    ASSERT_EQ(data.ground_truth[k * per_keyframe].stamp, fix.stamp);
    ASSERT_TRUE(MakePositionFactor(Pose3Key(k), fix.position,
                                   Eigen::Matrix3d::Identity() / (0.1 * 0.1),
                                   config.lever_arm, &f, &error));
    add(f);
  }

  // chi2 of the ground truth: ~ chi2(residuals), within 4 sigma.
  Graph truth_graph;
  for (const auto& [key, node] : graph.nodes()) {
    const InertialGroundTruth& g = data.ground_truth[key.id * per_keyframe];
    std::vector<double> value;
    if (key.kind == NodeKind::kPose3) value = Pose3Value(g.pose);
    if (key.kind == NodeKind::kVelocity3) {
      value = {g.velocity.x(), g.velocity.y(), g.velocity.z()};
    }
    if (key.kind == NodeKind::kImuBias) {
      value.assign(g.bias.data(), g.bias.data() + 6);
    }
    std::copy(value.begin(), value.end(),
              truth_graph.AddNode(key, value)->value.begin());
  }
  for (const auto& [id, factor] : graph.factors()) {
    ASSERT_GE(truth_graph.AddFactor(factor), 0);
  }
  const double truth_chi2 = truth_graph.Chi2();
  EXPECT_NEAR(truth_chi2, residuals, 4.0 * std::sqrt(2.0 * residuals))
      << "residuals " << residuals;

  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary summary = Optimize(&graph, options, nullptr);
  ASSERT_TRUE(summary.usable) << summary.termination;
  // The optimum's chi2 has residuals - parameters degrees of freedom.
  const int parameters = num_keyframes * 15;
  const int dof = residuals - parameters;
  EXPECT_NEAR(summary.final_chi2, dof, 4.0 * std::sqrt(2.0 * dof))
      << "dof " << dof;
  // Accuracy and consistency (NEES against the marginal covariances).
  std::vector<Key> keys;
  for (int k = 0; k < num_keyframes; ++k) {
    keys.push_back(Pose3Key(k));
    keys.push_back(VelocityKey(k));
    keys.push_back(ImuBiasKey(k));
  }
  std::map<Key, Eigen::MatrixXd> cov;
  ASSERT_TRUE(ComputeMarginals(&graph, keys, &cov, &error)) << error;
  double sum_sq = 0.0, nees_pose = 0.0, nees_vel = 0.0, nees_bias = 0.0;
  double bias_error = 0.0, bias_initial_error = 0.0;
  const SE3Manifold se3;
  for (int k = 0; k < num_keyframes; ++k) {
    const InertialGroundTruth& g = data.ground_truth[k * per_keyframe];
    const Node& xn = *graph.FindNode(Pose3Key(k));
    sum_sq += (NodePose3(xn).t - g.pose.t).squaredNorm();
    Eigen::Matrix<double, 6, 1> dx;
    const std::vector<double> xt = Pose3Value(g.pose);
    se3.Minus(xt.data(), xn.value.data(), dx.data());
    nees_pose += dx.dot(cov[Pose3Key(k)].ldlt().solve(dx));
    const Eigen::Vector3d dv =
        g.velocity - Eigen::Map<const Eigen::Vector3d>(
                         graph.FindNode(VelocityKey(k))->value.data());
    nees_vel += dv.dot(cov[VelocityKey(k)].ldlt().solve(dv));
    const ImuBias db =
        g.bias -
        Eigen::Map<const ImuBias>(graph.FindNode(ImuBiasKey(k))->value.data());
    nees_bias += db.dot(cov[ImuBiasKey(k)].ldlt().solve(db));
    bias_error += db.tail<3>().norm();
    bias_initial_error += g.bias.tail<3>().norm();
  }
  nees_pose /= num_keyframes;
  nees_vel /= num_keyframes;
  nees_bias /= num_keyframes;
  const double rmse = std::sqrt(sum_sq / num_keyframes);
  EXPECT_LT(rmse, 0.1);  // The fixes alone: 0.1 m per axis, every 1 s.
  // Averages over the keyframes of one run (strongly correlated): a wide
  // band around the state dimension, far from the factor 4 a wrong
  // covariance convention (e.g. half angles) would give.
  EXPECT_GT(nees_pose, 6.0 / 4.0);
  EXPECT_LT(nees_pose, 6.0 * 3.0);
  EXPECT_GT(nees_vel, 3.0 / 4.0);
  EXPECT_LT(nees_vel, 3.0 * 3.0);
  EXPECT_GT(nees_bias, 6.0 / 4.0);
  EXPECT_LT(nees_bias, 6.0 * 3.0);
  // The accelerometer bias is estimated: better than the zero prior.
  EXPECT_LT(bias_error, 0.7 * bias_initial_error);
  std::printf(
      "NEES pose %.2f (6), velocity %.2f (3), bias %.2f (6); "
      "accel bias error %.4f vs %.4f initial\n",
      nees_pose, nees_vel, nees_bias, bias_error / num_keyframes,
      bias_initial_error / num_keyframes);
  std::printf(
      "batch: %d keyframes, %d residuals, truth chi2 %.1f, final "
      "chi2 %.1f (dof %d), position RMSE %.4f m, %d iterations, "
      "%.3f s\n",
      num_keyframes, residuals, truth_chi2, summary.final_chi2, dof, rmse,
      summary.iterations, summary.solve_seconds);
}

}  // namespace
}  // namespace slam
