// Inertial estimation from IMU readings and position fixes: keyframes at a
// fixed rate (plus one at every position fix), IMU preintegration between
// keyframes (core/imu_preintegration.h), and either
//   * the sliding window (core/sliding_window.h): a fixed-lag smoother over
//     the newest keyframes, the oldest marginalised into a prior, or
//   * the global batch (core/optimizer.h) over all keyframes with the same
//     factors, for comparison and as the final refinement.
//
// States of keyframe k: Pose3Key(k) (body to world, the IMU frame),
// VelocityKey(k) (world), ImuBiasKey(k) (bg, ba). Factors:
//   keyframe 0:  prior on pose, velocity and bias (initial state and sigmas);
//   keyframe k:  IMU factor (k-1 -> k), bias random walk (k-1 -> k);
//   with a fix:  position factor (lever arm in the body frame).
// The readings between keyframes are integrated by IntegrateImuSamples
// (core/imu_preintegration.h) with the input's interpolation (linear: each
// interval with the mean of its end readings, second order; hold for the
// GTSAM CSV, whose rows each cover the following 5 ms).
// A position fix is attached to the keyframe at the IMU sample nearest in
// time; fixes farther than one IMU period from any sample are skipped.
#ifndef SLAM_FRONTENDS_INERTIAL_INERTIAL_ESTIMATOR_H_
#define SLAM_FRONTENDS_INERTIAL_INERTIAL_ESTIMATOR_H_

#include <Eigen/Core>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/imu_preintegration.h"
#include "core/sensors/inertial_data.h"
#include "core/sliding_window.h"
#include "core/trajectory.h"

namespace slam {

// Input: InertialData (core/sensors/): IMU readings, position fixes and
// the initial state when the file has one (GTSAM's "i" row; the simulator's
// true state). Without it: the initializer (inertial_initializer.h; still
// start, in-motion alignment from the fixes) gives the first state and its
// prior sigmas. The window's real-time (filter) estimates before the yaw is
// observable come from a pass without yaw information; when the alignment
// succeeds, the window restarts from the aligned state (a catch-up over the
// keyframes so far) and its estimates follow from there; the batch starts
// from dead reckoning from the aligned state. The pass without yaw
// information knows the yaw itself once its newest state's yaw sigma is
// below kMaxYawSigma (inertial_initializer.h): from that keyframe on its
// estimates count as knowing the yaw (until the alignment, if it comes).
// Once the alignment has a rough yaw (InertialInitialization::rough, sigma
// below kYawHintSigma), that pass restarts from it (a catch-up over the
// keyframes so far, with twice the rough sigma): from an arbitrary heading
// it fits the horizontal accelerations, mapped in the wrong direction, with
// tilt, which the biases then carry. That restarted pass iterates to
// convergence (its heading still moves by tens of degrees per update). The
// restarts replay the fixes the alignment used: they take its velocity, tilt
// and gyro bias as their start's mean with the sigmas from before it
// (InertialInitialization::unaligned_*), not counting those fixes twice.
// While that pass's yaw sigma is above kAlignmentMaxYawSigma, its
// marginalization prior is kept from knowing the heading better than 60
// degrees, or than its start when restarted from the rough yaw
// (inertial_estimator.cc): its heading is arbitrary, and a prior
// linearised there turns the later pull towards the true heading into a
// gyro bias.
struct InertialOptions {
  double keyframe_rate_hz = 10.0;
  ImuBias initial_bias = ImuBias::Zero();  // Prior mean of the first bias.
  ImuNoise noise;
  Eigen::Vector3d gravity = DefaultGravity();
  double position_sigma = 0.1;  // metres, per axis, of the fixes.
  Eigen::Vector3d lever_arm = Eigen::Vector3d::Zero();  // fix antenna, body.
  // Prior standard deviations of the initial state (known initial state).
  double prior_position_sigma = 0.01;   // metres
  double prior_rotation_sigma = 0.01;   // radians
  double prior_velocity_sigma = 0.1;    // m/s
  double prior_gyro_bias_sigma = 1e-2;  // rad/s
  double prior_accel_bias_sigma = 0.1;  // m/s^2
  // Gyro bias prior sigma of a start in motion (no still interval to
  // measure the bias, no initial state): the sensor's turn-on bias, around
  // initial_bias (inertial_initializer.h).
  double moving_start_gyro_bias_sigma = 1e-2;  // rad/s
  SlidingWindowOptions window;  // prior_builder set by the estimator.
  // Marginal covariance of the newest keyframe after every window update
  // (for consistency checks; costs a covariance computation per update).
  bool newest_covariance = false;
  // The same joint covariance of every keyframe at its fixed-lag (smoothed)
  // value: right before it leaves the window (SlidingWindowOptions::
  // final_covariances).
  bool smoothed_covariance = false;
  bool batch_verbose = false;
};

struct InertialState {
  TimeNs stamp = 0;
  NavState state;
  ImuBias bias = ImuBias::Zero();
};

struct InertialRun {
  // One entry per keyframe.
  std::vector<InertialState> filter;    // Newest state right after its update.
  std::vector<InertialState> smoothed;  // Window: value when marginalised
                                        // (fixed lag); batch: the optimum.
  // With newest_covariance: 15x15 joint covariance (cross-covariances
  // included) over (pose rho, phi (body, translation first), velocity, bias)
  // of the newest keyframe after each update, as `filter`.
  std::vector<Eigen::MatrixXd> newest_covariance;
  // With smoothed_covariance: the same for `smoothed` (window only).
  std::vector<Eigen::MatrixXd> smoothed_covariance;
  std::vector<double> update_seconds;  // Window updates.
  double total_seconds = 0.0;
  int num_fixes_used = 0;
  double final_chi2 = 0.0;  // Batch: chi2 at the optimum.
  // Initialization (frontends/inertial/inertial_initializer.h) when the
  // input has no initial state: its one-line summary, whether the yaw
  // became observable and after how many seconds of data; the first
  // filter_yaw_unknown `filter` states were estimated without yaw
  // information (their heading is arbitrary, their covariance says so).
  // yaw_from_window: the yaw became known from the window's own estimate
  // (its newest state's yaw sigma below kMaxYawSigma) before the alignment
  // had it; the estimates from then on are that window's.
  std::string initialization_summary;
  bool yaw_observable = true;
  bool yaw_from_window = false;
  double yaw_observable_after_seconds = 0.0;
  size_t filter_yaw_unknown = 0;
};

// The keyframes: sample index of each keyframe and the fix attached to it.
struct KeyframePlan {
  std::vector<size_t> sample;  // Index into data.imu.
  std::vector<int> fix;        // Index into data.positions or -1.
  int skipped_fixes = 0;
};
bool PlanKeyframes(const InertialData& data, double keyframe_rate_hz,
                   KeyframePlan* plan, std::string* error);

// Runs the sliding window over all the data. `progress` (may be nullptr)
// gets a line every ~10% and a summary line.
bool RunSlidingWindow(const InertialData& data, const InertialOptions& options,
                      InertialRun* run, std::ostream* progress,
                      std::string* error);

// The global batch over all keyframes. Initial values: `init` (one state per
// keyframe of the plan, e.g. a window run's smoothed states) when not empty,
// otherwise dead reckoning from the initial state (reset to the fixes).
bool RunBatch(const InertialData& data, const InertialOptions& options,
              const std::vector<InertialState>& init, InertialRun* run,
              std::ostream* progress, std::string* error);

Trajectory ToTrajectory(const std::vector<InertialState>& states);

}  // namespace slam

#endif  // SLAM_FRONTENDS_INERTIAL_INERTIAL_ESTIMATOR_H_
