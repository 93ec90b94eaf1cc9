#include "frontends/inertial/inertial_estimator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/graph.h"
#include "core/optimizer.h"
#include "factors/inertial_factors.h"
#include "factors/marginalization_prior.h"
#include "factors/pose_factors.h"
#include "frontends/inertial/inertial_initializer.h"

namespace slam {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// Preintegrates the readings between samples a and b (a < b).
bool Preintegrate(const InertialData& data, size_t a, size_t b,
                  const InertialOptions& options, const ImuBias& bias_lin,
                  PreintegratedImu* pim, std::string* error) {
  *pim = PreintegratedImu(options.noise, bias_lin, options.gravity);
  if (!IntegrateImuSamples(data.imu, data.imu[a].stamp, data.imu[b].stamp, pim,
                           data.interpolation)) {
    *error = "IMU readings " + std::to_string(a) + ".." + std::to_string(b) +
             ": cannot integrate (non-finite value)";
    return false;
  }
  return true;
}

// The initial state and the prior sigmas (position, rotation, velocity,
// biases); the rotation sigma about the world vertical (yaw) separately.
struct InitialGuess {
  InertialState state;
  double position_sigma, rotation_sigma, yaw_sigma, velocity_sigma;
  double gyro_bias_sigma, accel_bias_sigma;
};

// The input's initial state, or the initializer's (inertial_initializer.h).
InitialGuess MakeInitialGuess(const InertialData& data,
                              const InertialOptions& options,
                              const InertialInitialization& init) {
  InitialGuess guess;
  guess.state.stamp = data.imu.front().stamp;
  guess.state.bias = options.initial_bias;
  guess.gyro_bias_sigma = options.prior_gyro_bias_sigma;
  guess.accel_bias_sigma = options.prior_accel_bias_sigma;
  if (data.has_initial_state) {
    guess.state.state = data.initial_state;
    guess.position_sigma = options.prior_position_sigma;
    guess.rotation_sigma = options.prior_rotation_sigma;
    guess.yaw_sigma = options.prior_rotation_sigma;
    guess.velocity_sigma = options.prior_velocity_sigma;
    return guess;
  }
  guess.state = init.state;
  guess.position_sigma = init.position_sigma;
  guess.yaw_sigma = init.yaw_sigma;
  guess.accel_bias_sigma = init.accel_bias_sigma;
  // The estimators replay the fixes the alignment used: its velocity, tilt
  // and gyro bias are the start's mean, with the sigmas they had before it
  // (8 simulated 90 s gentle flights of the benchmark's kind, seeds 61-68:
  // bias NEES after 10 s 9.95 -> 8.52 on average; a still start's sigmas are
  // unchanged).
  guess.rotation_sigma = init.unaligned_tilt_sigma;
  guess.velocity_sigma = init.unaligned_velocity_sigma;
  guess.gyro_bias_sigma = init.unaligned_gyro_bias_sigma;
  return guess;
}

// The guess before the yaw is observable: the initializer's state with its
// yaw removed (heading 0 is as good as any) and no yaw information, the
// position at the first fix, velocity 0 (known only at a still start).
InitialGuess YawUnknownGuess(const InertialData& data,
                             const InertialOptions& options,
                             const InitialGuess& aligned,
                             const InertialInitialization& init) {
  InitialGuess guess = aligned;
  Eigen::Vector3d up = -options.gravity;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitZ();
  up.normalize();
  const Eigen::Matrix3d r = aligned.state.state.pose.q.toRotationMatrix();
  Eigen::Vector3d x = r.col(0);
  if ((x - x.dot(up) * up).norm() < 0.1) x = r.col(1);
  // Heading of x about `up`, measured from the world axis most
  // perpendicular to up.
  Eigen::Vector3d ref = Eigen::Vector3d::UnitX();
  if (std::abs(ref.dot(up)) > 0.9) ref = Eigen::Vector3d::UnitY();
  ref = (ref - ref.dot(up) * up).normalized();
  const double yaw =
      std::atan2(up.dot(ref.cross(x)), ref.dot(x - x.dot(up) * up));
  guess.state.state.pose.q =
      Eigen::Quaterniond(Eigen::AngleAxisd(-yaw, up) * r).normalized();
  guess.state.state.pose.t.setZero();
  for (const PositionFix& f : data.positions) {
    if (f.stamp >= data.imu.front().stamp) {
      guess.state.state.pose.t = f.position;
      break;
    }
  }
  guess.position_sigma = data.positions.empty() ? 1.0 : options.position_sigma;
  guess.state.state.velocity.setZero();
  guess.velocity_sigma = init.still_start ? init.velocity_sigma : 1.0;
  guess.yaw_sigma = M_PI;
  // This pass replays no alignment: it keeps the tilt sigma the initializer
  // ends with, as before. With the 0.1 rad of a moving start before the
  // alignment it dead-reckons more loosely between sparse fixes (benchmark,
  // real-time ATE with 1 Hz fixes: 60 s 0.310 -> 0.345 m, 200 s 0.125 ->
  // 0.148 m).
  guess.rotation_sigma = init.tilt_sigma;
  if (!init.still_start) {
    // A moving start's gyro bias comes from the alignment, which ends where
    // this pass ends: before then only the configured prior is known.
    guess.state.bias = options.initial_bias;
    guess.gyro_bias_sigma = options.moving_start_gyro_bias_sigma;
    guess.accel_bias_sigma = options.prior_accel_bias_sigma;
  }
  return guess;
}

// Factors of keyframe k (k = 0: priors), given the preintegration from k-1.
bool KeyframeFactors(const InertialData& data, const KeyframePlan& plan,
                     size_t k, const InertialOptions& options,
                     const InitialGuess& guess, const PreintegratedImu* pim,
                     std::vector<Factor>* factors, int* fixes_used,
                     std::string* error) {
  factors->clear();
  const int64_t id = static_cast<int64_t>(k);
  Factor f;
  if (k == 0) {
    Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
    info.diagonal().head<3>().setConstant(
        1.0 / (guess.position_sigma * guess.position_sigma));
    // MakePriorSE3's rotation error is the quaternion vector (half angle)
    // in the prior's body frame; the yaw sigma applies about world up.
    Eigen::Vector3d up = -options.gravity;
    if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_body =
        guess.state.state.pose.q.conjugate() * up.normalized();
    const double tilt_info =
        4.0 / (guess.rotation_sigma * guess.rotation_sigma);
    const double yaw_info = 4.0 / (guess.yaw_sigma * guess.yaw_sigma);
    info.bottomRightCorner<3, 3>() =
        tilt_info * Eigen::Matrix3d::Identity() +
        (yaw_info - tilt_info) * up_body * up_body.transpose();
    if (!MakePriorSE3(Pose3Key(0), guess.state.state.pose, info, &f, error)) {
      return false;
    }
    factors->push_back(f);
    if (!MakePriorVelocity(VelocityKey(0), guess.state.state.velocity,
                           Eigen::Matrix3d::Identity() /
                               (guess.velocity_sigma * guess.velocity_sigma),
                           &f, error)) {
      return false;
    }
    factors->push_back(f);
    Eigen::Matrix<double, 6, 6> bias_info = Eigen::Matrix<double, 6, 6>::Zero();
    bias_info.diagonal().head<3>().setConstant(
        1.0 / (guess.gyro_bias_sigma * guess.gyro_bias_sigma));
    bias_info.diagonal().tail<3>().setConstant(
        1.0 / (guess.accel_bias_sigma * guess.accel_bias_sigma));
    if (!MakePriorBias(ImuBiasKey(0), guess.state.bias, bias_info, &f, error)) {
      return false;
    }
    factors->push_back(f);
  } else {
    if (!MakeImuFactor(Pose3Key(id - 1), VelocityKey(id - 1),
                       ImuBiasKey(id - 1), Pose3Key(id), VelocityKey(id), *pim,
                       &f, error)) {
      return false;
    }
    factors->push_back(f);
    if (!MakeBiasRandomWalk(ImuBiasKey(id - 1), ImuBiasKey(id), options.noise,
                            pim->delta_t(), &f, error)) {
      return false;
    }
    factors->push_back(f);
  }
  if (plan.fix[k] >= 0) {
    const double s = options.position_sigma;
    if (!MakePositionFactor(Pose3Key(id), data.positions[plan.fix[k]].position,
                            Eigen::Matrix3d::Identity() / (s * s),
                            options.lever_arm, &f, error)) {
      return false;
    }
    factors->push_back(f);
    ++*fixes_used;
  }
  return true;
}

std::vector<SlidingWindow::NodeValue> StateNodes(int64_t id,
                                                 const InertialState& s) {
  const Eigen::Vector3d& v = s.state.velocity;
  return {
      {Pose3Key(id), Pose3Value(s.state.pose)},
      {VelocityKey(id), {v.x(), v.y(), v.z()}},
      {ImuBiasKey(id), std::vector<double>(s.bias.data(), s.bias.data() + 6)}};
}

// Reads keyframe id's states from node values.
InertialState ReadState(int64_t id, TimeNs stamp,
                        const std::vector<double>& pose,
                        const std::vector<double>& vel,
                        const std::vector<double>& bias) {
  InertialState s;
  s.stamp = stamp;
  s.state.pose = Pose3(Eigen::Vector3d(pose[0], pose[1], pose[2]),
                       Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]));
  s.state.velocity = Eigen::Vector3d(vel[0], vel[1], vel[2]);
  for (int i = 0; i < 6; ++i) s.bias[i] = bias[i];
  return s;
}

InertialState GraphState(const Graph& graph, int64_t id, TimeNs stamp) {
  InertialState s;
  s.stamp = stamp;
  GetInertialState(graph, id, &s.state, &s.bias);
  return s;
}

}  // namespace

bool PlanKeyframes(const InertialData& data, double keyframe_rate_hz,
                   KeyframePlan* plan, std::string* error) {
  *plan = KeyframePlan();
  if (data.imu.size() < 2) {
    *error = "need at least two IMU readings";
    return false;
  }
  if (!(keyframe_rate_hz > 0.0)) {
    *error = "keyframe rate must be > 0";
    return false;
  }
  std::vector<int64_t> dts;
  for (size_t s = 1; s < data.imu.size(); ++s) {
    if (data.imu[s].stamp <= data.imu[s - 1].stamp) {
      *error = "IMU stamps do not increase at reading " + std::to_string(s);
      return false;
    }
    dts.push_back(data.imu[s].stamp - data.imu[s - 1].stamp);
  }
  std::nth_element(dts.begin(), dts.begin() + dts.size() / 2, dts.end());
  const int64_t imu_period = dts[dts.size() / 2];
  // Fix -> nearest sample.
  std::vector<int> fix_at(data.imu.size(), -1);
  for (size_t f = 0; f < data.positions.size(); ++f) {
    const TimeNs t = data.positions[f].stamp;
    auto it = std::lower_bound(
        data.imu.begin(), data.imu.end(), t,
        [](const ImuSample& m, TimeNs v) { return m.stamp < v; });
    size_t s = static_cast<size_t>(it - data.imu.begin());
    if (s == data.imu.size() ||
        (s > 0 && t - data.imu[s - 1].stamp < data.imu[s].stamp - t)) {
      s = s == 0 ? 0 : s - 1;
    }
    if (std::llabs(data.imu[s].stamp - t) > imu_period) {
      ++plan->skipped_fixes;
      continue;
    }
    fix_at[s] = static_cast<int>(f);  // A later fix at the same sample wins.
  }
  const int64_t period =
      static_cast<int64_t>(std::llround(1e9 / keyframe_rate_hz));
  if (period < imu_period) {
    char text[160];
    std::snprintf(text, sizeof(text),
                  "the keyframe rate %g Hz is faster than the IMU (%g Hz): "
                  "at most one keyframe per IMU reading",
                  keyframe_rate_hz, 1e9 / static_cast<double>(imu_period));
    *error = text;
    return false;
  }
  // Keyframes at least half a period apart (a very short IMU interval gives
  // a near-singular preintegration covariance): a fix close after the last
  // keyframe moves that keyframe to the fix when it is an ordinary one, is
  // attached to it when it is at most one IMU period away, or is skipped.
  plan->sample.push_back(0);
  plan->fix.push_back(fix_at[0]);
  std::vector<bool> forced = {true};  // The first keyframe stays.
  for (size_t s = 1; s < data.imu.size(); ++s) {
    const int64_t since =
        data.imu[s].stamp - data.imu[plan->sample.back()].stamp;
    if (fix_at[s] >= 0 && since < period / 2) {
      if (!forced.back()) {
        plan->sample.back() = s;
        plan->fix.back() = fix_at[s];
        forced.back() = true;
      } else if (since <= imu_period && plan->fix.back() < 0) {
        plan->fix.back() = fix_at[s];
      } else {
        ++plan->skipped_fixes;
      }
      continue;
    }
    if (fix_at[s] >= 0 || since >= period - imu_period / 2) {
      plan->sample.push_back(s);
      plan->fix.push_back(fix_at[s]);
      forced.push_back(fix_at[s] >= 0);
    }
  }
  if (plan->sample.size() < 2) {
    *error = "the IMU log is shorter than one keyframe period";
    return false;
  }
  return true;
}

namespace {

// Standard deviation of the rotation about the world vertical (yaw) of the
// state `s` under the 15 x 15 covariance `c` (rho, phi, ...; phi the body
// right perturbation): a world rotation by psi about up is phi = psi R^T up.
double YawSigma(const InertialState& s, const Eigen::MatrixXd& c,
                const Eigen::Vector3d& gravity) {
  Eigen::Vector3d up = -gravity;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d u = s.state.pose.q.conjugate() * up.normalized();
  return std::sqrt(std::max(0.0, u.dot(c.block<3, 3>(3, 3) * u)));
}

// The smallest heading sigma the prior of the pass without yaw information
// may have (CapYawInformation): 60 degrees, where the first-order model of a
// heading change is off by half its size (1 - cos 60 deg = 0.5). Measured on 14
// simulated gentle flights (moving start, EuRoC unit's gyro bias): mean bias
// NEES after 10 s 7.74 without the cap, 6.36 / 6.30 / 8.32 with 30 / 60 / 180
// degrees (180: the pose NEES rises to 10.4); on V1_02 with 1 Hz fixes the
// real-time ATE moves from 0.192 to 0.193 / 0.202 m with 60 / 180 degrees.
constexpr double kYawUnknownPriorSigma = 60.0 * M_PI / 180.0;

// Keeps a marginalization prior from knowing the heading better than
// `floor_sigma`: an unknown offset psi ~ N(0, c) of each pose's attitude
// about world up (tangent phi = psi R0^T up at the prior's linearization
// point; position, velocity and bias kept) is added and marginalised, with
// c = floor_sigma^2 - (the prior's own yaw variance) when positive. In
// least-squares form, with a = J0 e the prior's response to that rotation,
// minimising |J0 (d + e psi) + r0|^2 + psi^2 / c over psi leaves
// |N (J0 d + r0)|^2 with N^T N = I - g a a^T / a^T a, g = c a^T a /
// (1 + c a^T a): J0 -> N J0, r0 -> N r0 (N = I - b a a^T / a^T a, b = 1 -
// sqrt(1 - g)).
void CapYawInformation(const Eigen::Vector3d& up, double floor_sigma,
                       LinearPrior* prior) {
  int offset = 0;
  for (size_t i = 0; i < prior->keys.size(); ++i) {
    const int size = prior->tangent_sizes[i];
    if (prior->keys[i].kind == NodeKind::kPose3 && size == 6 &&
        prior->x0[i].size() == 7) {
      const std::vector<double>& x = prior->x0[i];
      const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);
      Eigen::VectorXd e = Eigen::VectorXd::Zero(prior->j0.cols());
      e.segment<3>(offset + 3) = q.normalized().conjugate() * up;
      const Eigen::VectorXd a = prior->j0 * e;
      const double aa = a.squaredNorm();
      // The prior's yaw variance e^T H^+ e (the window's rank cut).
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(
          prior->j0.transpose() * prior->j0);
      const Eigen::VectorXd& values = solver.eigenvalues();
      const double cut = 1e-14 * std::max(values.maxCoeff(), 0.0);
      double variance = 0.0;
      for (int j = 0; j < values.size(); ++j) {
        const double p = solver.eigenvectors().col(j).dot(e);
        variance += values[j] > cut ? p * p / values[j] : 0.0;
      }
      const double c = floor_sigma * floor_sigma - variance;
      if (aa > 0.0 && c > 0.0 && std::isfinite(variance)) {
        const double g = c * aa / (1.0 + c * aa);
        const double beta = (1.0 - std::sqrt(1.0 - g)) / aa;
        const Eigen::RowVectorXd at_j = a.transpose() * prior->j0;
        prior->j0 -= beta * a * at_j;
        prior->r0 -= beta * a * a.dot(prior->r0);
      }
    }
    offset += size;
  }
  prior->hessian = prior->j0.transpose() * prior->j0;
  prior->gradient = prior->j0.transpose() * prior->r0;
}

// LM iterations per update of the pass restarted from the rough yaw (the
// configured cap when larger). That pass runs only between the rough yaw and
// the yaw, and its heading is still moving by tens of degrees per update
// there: the 200 s, 1 Hz keyframe entry of scripts/benchmark_inertial.py
// published its second keyframe 25 deg off after the 10 iterations of the
// configured cap (LM rejects its first Gauss-Newton steps along the heading)
// against 7 deg converged (20-25 iterations); on the 10 Hz entries its updates
// converge within the configured cap.
constexpr int kRoughPassMaxIterations = 50;

// One pass of the sliding window from `guess` over keyframes [0, k_end):
// the filter states (and covariances) into *run; with `finish`, the
// smoothed states of all keyframes too. With `yaw_known_at` (a pass without
// yaw information): the first keyframe from `yaw_hint_stamp` on whose
// newest-state yaw sigma is below kMaxYawSigma goes there (k_end when none
// is). `min_iterations`: the LM iteration cap per update is at least this.
bool RunWindowPass(const InertialData& data, const KeyframePlan& plan,
                   const InertialOptions& options, const InitialGuess& guess,
                   size_t k_end, bool finish, const char* label,
                   InertialRun* run, std::ostream* progress, std::string* error,
                   size_t* yaw_known_at = nullptr, TimeNs yaw_hint_stamp = 0,
                   int min_iterations = 0) {
  if (yaw_known_at != nullptr) *yaw_known_at = k_end;
  SlidingWindowOptions window_options = options.window;
  window_options.max_iterations =
      std::max(window_options.max_iterations, min_iterations);
  Eigen::Vector3d up = -options.gravity;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitZ();
  up.normalize();
  // The pass without yaw information: while its own yaw sigma is above
  // kAlignmentMaxYawSigma (the bar an alignment's yaw must pass to become
  // the restart's linearization point), its prior may not know the heading
  // better than kYawUnknownPriorSigma (CapYawInformation). Its heading is
  // arbitrary, radians off; a prior linearised there that holds the
  // heading's information turns the data's later pull towards the true
  // heading into a gyro bias (simulated gentle flights,
  // tests/inertial_initializer_test.cc: z bias 0.15-0.27 rad/s off with a
  // sigma of 0.02). Restarted from the alignment's rough yaw
  // (InertialInitialization::rough), the prior may know it as well as that
  // start did: the cap is the start's yaw sigma when smaller (14 simulated
  // gentle flights, bias NEES after 10 s: 5.35 with 60 deg, 5.28 with the
  // start's sigma; without a cap the z bias error reached 3.4 sigma before the
  // yaw was known).
  double newest_yaw_sigma = M_PI;
  const bool yaw_unknown_pass = yaw_known_at != nullptr;
  const double cap_sigma = std::min(kYawUnknownPriorSigma, guess.yaw_sigma);
  window_options.prior_builder = [&](const LinearPrior& prior, Factor* factor,
                                     std::string* builder_error) {
    if (!yaw_unknown_pass || newest_yaw_sigma <= kAlignmentMaxYawSigma) {
      return MakeMarginalizationPrior(prior, factor, builder_error);
    }
    LinearPrior capped = prior;
    CapYawInformation(up, cap_sigma, &capped);
    return MakeMarginalizationPrior(capped, factor, builder_error);
  };
  // The information of a window spans many decades: a start with a few
  // degrees of tilt left, then 19 s without fixes (dead reckoning, position
  // sigma of tens of metres) against the preintegration's attitude
  // information puts the position's eigenvalues 1e-13 below the largest,
  // and the default cut of 1e-12 dropped them (covariance "rank deficient",
  // tests/inertial_initializer_test.cc, SparseFixesAndImuGapsAreReported).
  // 1e-14 is still 50 x the eigensolver's rounding (eps times the largest).
  window_options.marginalization.rank_threshold = 1e-14;
  window_options.final_covariances = options.smoothed_covariance;
  SlidingWindow window(window_options);
  const size_t n = k_end;
  std::vector<Factor> factors;
  PreintegratedImu pim(options.noise, ImuBias::Zero(), options.gravity);
  size_t next_report = 1;
  for (size_t k = 0; k < n; ++k) {
    const int64_t id = static_cast<int64_t>(k);
    const TimeNs stamp = data.imu[plan.sample[k]].stamp;
    InertialState predicted = guess.state;
    if (k > 0) {
      const InertialState prev = GraphState(window.graph(), id - 1,
                                            data.imu[plan.sample[k - 1]].stamp);
      if (!Preintegrate(data, plan.sample[k - 1], plan.sample[k], options,
                        prev.bias, &pim, error)) {
        return false;
      }
      predicted.state = pim.Predict(prev.state, prev.bias);
      predicted.bias = prev.bias;
    }
    predicted.stamp = stamp;
    if (!KeyframeFactors(data, plan, k, options, guess, k > 0 ? &pim : nullptr,
                         &factors, &run->num_fixes_used, error) ||
        !window.AddKeyframe(stamp, StateNodes(id, predicted),
                            std::move(factors), error)) {
      *error = "keyframe " + std::to_string(k) + ": " + *error;
      return false;
    }
    WindowUpdateStats stats;
    if (!window.Update(&stats, error)) {
      *error = "keyframe " + std::to_string(k) + ": " + *error;
      return false;
    }
    run->filter.push_back(GraphState(window.graph(), id, stamp));
    const bool track_yaw = yaw_known_at != nullptr && *yaw_known_at == k_end;
    if (options.newest_covariance || track_yaw) {
      Eigen::MatrixXd c;
      if (!window.JointCovariance(
              {Pose3Key(id), VelocityKey(id), ImuBiasKey(id)}, &c, error)) {
        *error = "keyframe " + std::to_string(k) + ": " + *error;
        return false;
      }
      if (track_yaw) {
        newest_yaw_sigma = YawSigma(run->filter.back(), c, options.gravity);
      }
      if (track_yaw && stamp >= yaw_hint_stamp &&
          newest_yaw_sigma < kMaxYawSigma) {
        *yaw_known_at = k;
      }
      if (options.newest_covariance) run->newest_covariance.push_back(c);
    }
    if (progress != nullptr && (k + 1) * 10 >= next_report * n) {
      const TimingSummary t = SummarizeTimes(window.update_seconds());
      char line[200];
      std::snprintf(line, sizeof(line),
                    "%s: keyframe %zu/%zu t=%.2f s, update median %.2f ms "
                    "p99 %.2f ms, chi2 %.4g\n",
                    label, k + 1, n,
                    NsToSeconds(stamp - data.imu.front().stamp), 1e3 * t.median,
                    1e3 * t.p99, stats.final_chi2);
      *progress << line;
      while ((k + 1) * 10 >= next_report * n) ++next_report;
    }
  }
  run->update_seconds = window.update_seconds();
  if (!finish) return true;
  window.Finish();
  if (options.smoothed_covariance) {
    // Keyframes leave the window in order, Finish() adds the rest in order.
    for (const auto& [keys, cov] : window.final_covariances()) {
      if (cov.rows() != 15) {
        *error = "keyframe " + std::to_string(run->smoothed_covariance.size()) +
                 ": no covariance at its smoothed value";
        return false;
      }
      run->smoothed_covariance.push_back(cov);
    }
  }
  for (size_t k = 0; k < n; ++k) {
    const int64_t id = static_cast<int64_t>(k);
    const auto& v = window.final_values();
    run->smoothed.push_back(ReadState(id, data.imu[plan.sample[k]].stamp,
                                      v.at(Pose3Key(id)), v.at(VelocityKey(id)),
                                      v.at(ImuBiasKey(id))));
  }
  return true;
}

void CopyInitialization(const InertialData& data,
                        const InertialInitialization& init, InertialRun* run) {
  run->initialization_summary = init.summary;
  run->yaw_observable = data.has_initial_state || init.yaw_observable;
  run->yaw_observable_after_seconds =
      data.has_initial_state
          ? 0.0
          : NsToSeconds(init.yaw_observable_stamp - data.imu.front().stamp);
}

// Real time: `before`'s estimates up to keyframe k; at k the catch-up of
// `after` (restarted from a better start) over keyframes 0..k.
void SpliceRealTime(size_t k_restart, bool covariance,
                    const InertialRun& before, InertialRun* after) {
  double catch_up = 0.0;
  for (size_t k = 0; k <= k_restart; ++k) catch_up += after->update_seconds[k];
  for (size_t k = 0; k < k_restart; ++k) {
    after->filter[k] = before.filter[k];
    after->update_seconds[k] = before.update_seconds[k];
    if (covariance) after->newest_covariance[k] = before.newest_covariance[k];
  }
  after->update_seconds[k_restart] = catch_up;
}

}  // namespace

bool RunSlidingWindow(const InertialData& data, const InertialOptions& options,
                      InertialRun* run, std::ostream* progress,
                      std::string* error) {
  *run = InertialRun();
  const auto start = std::chrono::steady_clock::now();
  KeyframePlan plan;
  if (!PlanKeyframes(data, options.keyframe_rate_hz, &plan, error)) {
    return false;
  }
  InertialInitialization init;
  if (!data.has_initial_state &&
      !InitializeInertial(data, options, &init, error)) {
    return false;
  }
  CopyInitialization(data, init, run);
  const InitialGuess guess = MakeInitialGuess(data, options, init);
  const size_t n = plan.sample.size();
  // Keyframes before the yaw is observable: the real-time estimate has no
  // yaw information (pass A); from then on the window started from the
  // aligned state (pass B, which re-runs the first keyframes at that time).
  size_t k_obs = 0;
  if (!data.has_initial_state) {
    while (k_obs < n &&
           data.imu[plan.sample[k_obs]].stamp < init.yaw_observable_stamp) {
      ++k_obs;
    }
    if (!init.yaw_observable) k_obs = n;
  }
  // With a rough alignment before that (InertialInitialization::rough),
  // the pass without yaw information restarts from it at its keyframe
  // k_rough (pass A', a catch-up over the keyframes so far): from an
  // arbitrary heading, radians off, pass A maps the horizontal accelerations
  // in the wrong direction and fits them with tilt, which the x / y gyro and
  // the accelerometer biases carry and keep (the benchmark's gentle flight:
  // bias NEES 52 over 10-13 s; with the rough yaw 8-9).
  size_t k_rough = k_obs;
  if (k_obs > 0 && init.rough != nullptr) {
    k_rough = 0;
    while (k_rough < k_obs &&
           data.imu[plan.sample[k_rough]].stamp < init.yaw_hint_stamp) {
      ++k_rough;
    }
    if (k_rough == 0) k_rough = k_obs;  // Nothing to publish before it.
  }
  InertialRun pass_a;
  // The pass without yaw information also watches its own yaw sigma: a
  // window that knows the yaw before the alignment does publishes its
  // estimates as known from then on.
  size_t k_window = k_obs;
  if (k_obs > 0) {
    if (!RunWindowPass(data, plan, options,
                       YawUnknownGuess(data, options, guess, init), k_rough,
                       k_rough == n, "window (yaw unknown)", &pass_a, progress,
                       error, &k_window, init.yaw_hint_stamp)) {
      return false;
    }
    if (k_window == k_rough) k_window = k_obs;
  }
  if (k_rough < k_obs) {
    InertialRun pass_rough;
    size_t k_window_rough = k_obs;
    if (!RunWindowPass(data, plan, options,
                       MakeInitialGuess(data, options, *init.rough), k_obs,
                       k_obs == n, "window (rough yaw)", &pass_rough, progress,
                       error, &k_window_rough, init.yaw_hint_stamp,
                       kRoughPassMaxIterations)) {
      return false;
    }
    if (k_window == k_obs) k_window = k_window_rough;
    SpliceRealTime(k_rough, options.newest_covariance, pass_a, &pass_rough);
    pass_a = std::move(pass_rough);
  }
  if (k_obs == n) {  // The alignment never succeeded.
    pass_a.initialization_summary = run->initialization_summary;
    pass_a.yaw_observable = run->yaw_observable;
    pass_a.yaw_observable_after_seconds = run->yaw_observable_after_seconds;
    *run = std::move(pass_a);
  } else {
    if (!RunWindowPass(data, plan, options, guess, n, true, "window", run,
                       progress, error)) {
      return false;
    }
    if (k_obs > 0) {
      SpliceRealTime(k_obs, options.newest_covariance, pass_a, run);
    }
  }
  run->filter_yaw_unknown = std::min(k_window, k_obs);
  if (k_window < k_obs) {
    run->yaw_observable = true;
    run->yaw_from_window = true;
    run->yaw_observable_after_seconds = NsToSeconds(
        data.imu[plan.sample[k_window]].stamp - data.imu.front().stamp);
    char line[200];
    std::snprintf(line, sizeof(line),
                  "; the window's own yaw sigma fell below %.0f deg after "
                  "%.2f s (keyframe %zu): its estimates know the yaw from then "
                  "on",
                  kMaxYawSigma * 180.0 / M_PI,
                  run->yaw_observable_after_seconds, k_window);
    run->initialization_summary += line;
  }
  run->total_seconds = SecondsSince(start);
  if (progress != nullptr) {
    const TimingSummary t = SummarizeTimes(run->update_seconds);
    char line[240];
    std::snprintf(line, sizeof(line),
                  "window: %zu keyframes, %d fixes (%d skipped), window size "
                  "%d, update median %.2f ms p99 %.2f ms max %.2f ms, total "
                  "%.2f s\n",
                  n, run->num_fixes_used, plan.skipped_fixes,
                  options.window.window_size, 1e3 * t.median, 1e3 * t.p99,
                  1e3 * t.max, run->total_seconds);
    *progress << line;
  }
  return true;
}

bool RunBatch(const InertialData& data, const InertialOptions& options,
              const std::vector<InertialState>& init, InertialRun* run,
              std::ostream* progress, std::string* error) {
  *run = InertialRun();
  const auto start = std::chrono::steady_clock::now();
  KeyframePlan plan;
  if (!PlanKeyframes(data, options.keyframe_rate_hz, &plan, error)) {
    return false;
  }
  const size_t n = plan.sample.size();
  if (!init.empty() && init.size() != n) {
    *error = "batch initial values: " + std::to_string(init.size()) +
             " states for " + std::to_string(n) + " keyframes";
    return false;
  }
  InertialInitialization initialization;
  if (!data.has_initial_state &&
      !InitializeInertial(data, options, &initialization, error)) {
    return false;
  }
  CopyInitialization(data, initialization, run);
  const InitialGuess guess = MakeInitialGuess(data, options, initialization);
  Graph graph;
  std::vector<Factor> factors;
  PreintegratedImu pim(options.noise, ImuBias::Zero(), options.gravity);
  InertialState prev = guess.state;
  for (size_t k = 0; k < n; ++k) {
    const int64_t id = static_cast<int64_t>(k);
    const TimeNs stamp = data.imu[plan.sample[k]].stamp;
    InertialState value = init.empty() ? guess.state : init[k];
    if (k > 0) {
      if (!Preintegrate(data, plan.sample[k - 1], plan.sample[k], options,
                        prev.bias, &pim, error)) {
        return false;
      }
      if (init.empty()) {  // Dead reckoning, reset to the fix when present.
        value.state = pim.Predict(prev.state, prev.bias);
        value.bias = prev.bias;
        if (plan.fix[k] >= 0) {
          value.state.pose.t = data.positions[plan.fix[k]].position;
        }
      }
    }
    value.stamp = stamp;
    AddInertialState(&graph, id, stamp, value.state, value.bias);
    if (!KeyframeFactors(data, plan, k, options, guess, k > 0 ? &pim : nullptr,
                         &factors, &run->num_fixes_used, error)) {
      *error = "keyframe " + std::to_string(k) + ": " + *error;
      return false;
    }
    for (Factor& f : factors) graph.AddFactor(std::move(f));
    prev = value;
  }
  OptimizerOptions optimizer;
  optimizer.verbose = options.batch_verbose;
  optimizer.num_threads = 1;
  const OptimizerSummary summary = Optimize(&graph, optimizer, progress);
  if (!summary.usable) {
    *error = "batch optimization failed: " + summary.termination;
    return false;
  }
  run->final_chi2 = summary.final_chi2;
  for (size_t k = 0; k < n; ++k) {
    run->smoothed.push_back(GraphState(graph, static_cast<int64_t>(k),
                                       data.imu[plan.sample[k]].stamp));
  }
  run->total_seconds = SecondsSince(start);
  if (progress != nullptr) {
    char line[200];
    std::snprintf(line, sizeof(line),
                  "batch: %zu keyframes, %zu factors, chi2 %.6g -> %.6g in %d "
                  "iterations, %.3f s\n",
                  n, graph.NumFactors(), summary.initial_chi2,
                  summary.final_chi2, summary.iterations, run->total_seconds);
    *progress << line;
  }
  return true;
}

Trajectory ToTrajectory(const std::vector<InertialState>& states) {
  Trajectory t;
  for (const InertialState& s : states) t.push_back({s.stamp, s.state.pose});
  return t;
}

}  // namespace slam
