// Initialization of inertial estimation without ground truth: the state at
// the first IMU reading (frontends/inertial/inertial_estimator.h starts the
// sliding window and the batch from it) and the checks that the data can
// determine the state at all.
//
// Still start: the longest prefix of 0.5 s blocks in which the readings
// look like a body at rest (accelerometer norm within 0.5 m/s^2 of |g|,
// accelerometer std below 1 m/s^2 and gyroscope std below 0.1 rad/s per axis:
// tolerant of the vibration of a platform whose motors run) and the fixes in
// it stay within 4 sigma of their mean and show no motion: a straight-line
// fit through them has a velocity within 4 sigma of zero, and the still
// start counts only once that sigma is at most 0.15 m/s (the fixes of up to
// 1 s after a shorter still interval join the fit). An IMU cannot tell a
// slow steady turn from a gyroscope bias: a start in steady motion whose
// fixes show it is a moving start (bias from the configured prior). Over the
// still interval: gyroscope bias = mean gyroscope reading, roll and pitch
// from the mean accelerometer reading, velocity 0.
//
// In-motion alignment (yaw, velocity; tilt too without a still start), as
// GNSS/INS systems align: with the rotation dR(t) and the double integral
// dp(t) of the readings from t0 (the first IMU reading; gyroscope bias from
// the still start, else the configured initial bias), a fix z at t obeys
//   z - 1/2 g t^2 = p0 + v0 t + R0 (dp(t) + dR(t) lever_arm).
// With R0 = Rz(psi) R_tilt (roll and pitch from the mean accelerometer
// reading of the still interval, else of the first 0.5 s) this is linear in
// p0, v0, (cos psi, sin psi), plus a small horizontal term e u_z that
// absorbs a tilt error (magnified by gravity, u_z ~ g t^2 / 2), the
// readings' bias errors through the preintegration's bias Jacobians (body
// frame, so they turn with the body: bilinear in (cos psi, sin psi) and the
// bias, linear in their products), and a vertical 1/2 b t^2 for the
// accelerometer's scale along gravity: a generalised least-squares fit
// (tilt and biases with zero-mean priors of their sigmas) under the fixes'
// noise (position_sigma) and the integrated IMU noise, whose position error
// is correlated across the fixes: the gyroscope's white noise random-walks
// the tilt and gravity turns that into metres within 15 s at the EuRoC
// config's flight noise; a fit weighted by the fix noise alone explained
// that error with the biases and the yaw and believed it. The yaw standard
// deviation is the marginal of the fit's
// information (the inverse of its normal matrix, priors included), scaled
// up by the fit's chi2 per degree of freedom when above 1: the yaw is
// observable when the data carry the information, whatever the motion
// that carries it. Fixes are added one at a time in time order (causal);
// the yaw is observable at the first fix after which its standard deviation
// is below kAlignmentMaxYawSigma with at least 5 fixes; the prior then gets
// twice that sigma (at least 1 degree: the moving starts' yaw errors reach
// 2.4 of the fit's sigma, its linearisation in the bias and tilt). Without a
// still start the gyroscope bias is known only to its prior
// (moving_start_gyro_bias_sigma, the sensor's turn-on bias: several 0.01 rad/s
// on the EuRoC ADIS16448), and the heading drift it causes soon leaves the
// fit's first-order bias terms: the readings are re-integrated with the fit's
// gyro bias whenever it moves (Gauss-Newton on the bias, the prior kept on the
// configured bias), and the estimators start from that bias with the fit's
// sigma (within the prior's). Until then the estimators put no yaw information
// in the first prior (sigma 180 degrees), so the covariance of the published
// estimate shows it; the sliding window's own yaw estimate counts from the
// keyframe its yaw sigma falls below kMaxYawSigma (inertial_estimator.h; only
// once the alignment's is below kYawHintSigma). The first fit whose yaw sigma
// is below kYawHintSigma also gives a rough start (`rough`, built as the final
// one), from which the window's pass without yaw information restarts.
#ifndef SLAM_FRONTENDS_INERTIAL_INERTIAL_INITIALIZER_H_
#define SLAM_FRONTENDS_INERTIAL_INERTIAL_INITIALIZER_H_

#include <memory>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/sensors/inertial_data.h"
#include "frontends/inertial/inertial_estimator.h"

namespace slam {

// The window's own yaw is known once its standard deviation
// (inertial_estimator.h) is below this. 5 degrees: a yaw error
// that small is linearised with an error of 1 - cos(5 deg) = 0.4 %, and the
// window's yaw sigma on a gentle flight with the EuRoC noise settles near
// 3 degrees (tests/inertial_initializer_test.cc), so a first alignment
// cannot be asked for much better.
constexpr double kMaxYawSigma = 5.0 * M_PI / 180.0;
// The alignment's yaw is known once its sigma is below this: the sigma of a
// generalised least squares under the integrated IMU noise, 1.7 times that
// of the fix noise alone (which had kMaxYawSigma) on the benchmark's gentle
// flight 14 s in.
constexpr double kAlignmentMaxYawSigma = 2.0 * kMaxYawSigma;
// The window's own yaw sigma counts only once the alignment's is below this
// (twice kAlignmentMaxYawSigma, as the fix-noise-only alignment had it at
// twice its threshold):
// the window's marginal comes from Jacobians taken at its estimates
// (first-estimate Jacobians in its prior), and at a wrong heading and bias
// they show yaw information that is not in the data (constant velocity with
// the data sheet noise: the window's yaw sigma falls below 5 degrees in
// 8 s, the fix-noise-only alignment's stayed above 10); the alignment is
// linear in its unknowns and cannot.
constexpr double kYawHintSigma = 2.0 * kAlignmentMaxYawSigma;
// Fix-free stretches longer than this draw a warning (IMU alone drifts by
// metres within seconds: position error grows with the cube of time).
constexpr double kMaxFixGapSeconds = 10.0;
// IMU stamps jumping by more than this many median sample periods draw a
// warning naming the reading.
constexpr double kMaxImuGapPeriods = 4.0;

struct InertialInitialization {
  InertialState state;  // At data.imu.front().stamp.
  // Prior standard deviations of `state` (world frame; yaw about world z,
  // tilt about the horizontal axes).
  double position_sigma = 1.0;
  double velocity_sigma = 1.0;
  double tilt_sigma = 0.1;
  double yaw_sigma = M_PI;
  double gyro_bias_sigma = 0.01;
  double accel_bias_sigma = 0.1;
  // The sigmas of velocity, tilt and gyro bias before the alignment (the
  // IMU and the priors alone, no fix). The estimators replay the fixes the
  // alignment used, from the first keyframe on: they take the aligned
  // state's velocity, tilt and gyro bias as their start's mean with these
  // sigmas, not with the fit's, which would count those fixes twice
  // (inertial_estimator.cc, MakeInitialGuess). The yaw keeps the fit's
  // sigma, doubled: it is the linearisation point the window needs.
  double unaligned_velocity_sigma = 1.0;
  double unaligned_tilt_sigma = 0.1;
  double unaligned_gyro_bias_sigma = 0.01;
  bool still_start = false;
  double still_seconds = 0.0;
  bool yaw_observable = false;
  // Stamp of the last fix the alignment needed (the yaw is known from then
  // on); data.imu.back().stamp when yaw never became observable.
  TimeNs yaw_observable_stamp = 0;
  // Stamp of the first fix after which the alignment's yaw sigma was below
  // kYawHintSigma (max() when never): the window's own yaw counts from then.
  TimeNs yaw_hint_stamp = 0;
  int alignment_fixes = 0;
  // The alignment's first rough yaw, at yaw_hint_stamp (its sigma below
  // kYawHintSigma, not yet observable): the start it gives, as above (null
  // when there is none). The sliding window's pass without yaw information
  // restarts from it (inertial_estimator.h).
  std::shared_ptr<const InertialInitialization> rough;
  // Human-readable one-line summary.
  std::string summary;
};

// Computes the initialization from the data (no ground truth used). False
// only for data without IMU readings.
bool InitializeInertial(const InertialData& data,
                        const InertialOptions& options,
                        InertialInitialization* init, std::string* error);

// Problems that leave the state poorly determined, one message each:
// stretches without fixes longer than kMaxFixGapSeconds (at the start, in
// between, at the end), IMU stamp gaps beyond kMaxImuGapPeriods median
// periods (with the reading index; the EuRoC reader also names file and
// line, see datasets/imu_io.h). No fixes at all is not listed here: the
// command refuses that unless dead reckoning is asked for.
std::vector<std::string> InertialDataWarnings(const InertialData& data);

// The start from the ground truth instead (initial_state: ground_truth):
// drops the IMU readings before the first ground-truth state and starts
// there, bias included (*bias: the prior mean of the first keyframe's bias).
// False with a message when there is no ground truth or no IMU reading
// after its first state.
bool StartAtGroundTruth(InertialData* data, ImuBias* bias, std::string* error);

}  // namespace slam

#endif  // SLAM_FRONTENDS_INERTIAL_INERTIAL_INITIALIZER_H_
