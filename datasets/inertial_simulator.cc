#include "datasets/inertial_simulator.h"

#include <algorithm>
#include <cmath>

#include "datasets/simulation_random.h"
#include "datasets/trajectory_io.h"

namespace slam {
namespace {

bool NonNegative(double value, const char* name, std::string* error) {
  if (value >= 0.0 && std::isfinite(value)) return true;
  *error = std::string("inertial.") + name + " must be >= 0 and finite";
  return false;
}

bool Positive(double value, const char* name, std::string* error) {
  if (value > 0.0 && std::isfinite(value)) return true;
  *error = std::string("inertial.") + name + " must be > 0 and finite";
  return false;
}

Eigen::Vector3d Normal3(SimulationRandom* random) {
  const double x = random->Normal();
  const double y = random->Normal();
  const double z = random->Normal();
  return Eigen::Vector3d(x, y, z);
}

}  // namespace

bool ValidateInertialSimulationConfig(const InertialSimulationConfig& config,
                                      std::string* error) {
  if (!Positive(config.duration, "duration", error) ||
      !Positive(config.imu_rate, "imu_rate", error) ||
      !NonNegative(config.position_rate, "position_rate", error) ||
      !NonNegative(config.position_sigma, "position_sigma", error) ||
      !NonNegative(config.noise.gyro_noise_density, "gyro_noise_density",
                   error) ||
      !NonNegative(config.noise.accel_noise_density, "accel_noise_density",
                   error) ||
      !NonNegative(config.noise.gyro_random_walk, "gyro_random_walk", error) ||
      !NonNegative(config.noise.accel_random_walk, "accel_random_walk",
                   error)) {
    return false;
  }
  if (config.duration * config.imu_rate > 1e8) {
    *error = "inertial.duration * inertial.imu_rate must be at most 1e8";
    return false;
  }
  if (config.duration * config.position_rate > 1e8) {
    *error = "inertial.duration * inertial.position_rate must be at most 1e8";
    return false;
  }
  if (config.imu_rate > 1e6) {
    *error = "inertial.imu_rate must be at most 1e6 Hz";
    return false;
  }
  if (!config.lever_arm.allFinite() || !config.gravity.allFinite() ||
      !config.initial_gyro_bias.allFinite() ||
      !config.initial_accel_bias.allFinite()) {
    *error =
        "inertial: lever_arm, gravity and the initial biases must be "
        "finite";
    return false;
  }
  const LissajousParams& t = config.trajectory;
  if (!t.center.allFinite() || !t.amplitude.allFinite() ||
      !t.frequency.allFinite() || !t.phase.allFinite()) {
    *error = "inertial.trajectory values must be finite";
    return false;
  }
  return true;
}

bool SimulateInertial(const InertialSimulationConfig& config,
                      InertialData* data, std::string* error) {
  if (!ValidateInertialSimulationConfig(config, error)) return false;
  if (config.trajectory_file.empty()) {
    return SimulateInertial(config, LissajousTrajectory(config.trajectory),
                            data, error);
  }
  TrajectoryReadOptions options;
  options.kitti_times_path = config.trajectory_times_file;
  TrajectoryData recorded;
  if (!ReadTrajectory(config.trajectory_file, options, &recorded, error)) {
    return false;
  }
  SplineTrajectory spline;
  if (!spline.Fit(recorded.poses, config.trajectory_y_down, error)) {
    *error = config.trajectory_file + ": " + *error;
    return false;
  }
  return SimulateInertial(config, spline, data, error);
}

bool SimulateInertial(const InertialSimulationConfig& config_in,
                      const SmoothTrajectory& trajectory, InertialData* data,
                      std::string* error) {
  if (!ValidateInertialSimulationConfig(config_in, error)) return false;
  InertialSimulationConfig config = config_in;
  config.duration = std::min(config.duration, trajectory.duration());
  SimulationRandom random(config.seed);
  const ImuNoise& noise = config.noise;
  const double dt = 1.0 / config.imu_rate;
  const double sigma_g = noise.gyro_noise_density / std::sqrt(dt);
  const double sigma_a = noise.accel_noise_density / std::sqrt(dt);
  const double step_bg = noise.gyro_random_walk * std::sqrt(dt);
  const double step_ba = noise.accel_random_walk * std::sqrt(dt);

  InertialData out;
  out.gravity = config.gravity;
  const int64_t num_imu =
      static_cast<int64_t>(std::floor(config.duration * config.imu_rate)) + 1;
  out.imu.reserve(num_imu);
  out.ground_truth.reserve(num_imu);
  Eigen::Vector3d bg = config.initial_gyro_bias;
  Eigen::Vector3d ba = config.initial_accel_bias;
  for (int64_t k = 0; k < num_imu; ++k) {
    const TimeNs stamp = static_cast<TimeNs>(
        std::llround(static_cast<double>(k) * 1e9 / config.imu_rate));
    const TrajectorySample s = trajectory.Evaluate(NsToSeconds(stamp));
    InertialGroundTruth truth;
    truth.stamp = stamp;
    truth.pose = s.pose;
    truth.velocity = s.velocity;
    truth.bias << bg, ba;
    out.ground_truth.push_back(truth);
    ImuSample sample;
    sample.stamp = stamp;
    sample.gyro = s.omega + bg + sigma_g * Normal3(&random);
    sample.accel = s.pose.q.conjugate() * (s.acceleration - config.gravity) +
                   ba + sigma_a * Normal3(&random);
    out.imu.push_back(sample);
    bg += step_bg * Normal3(&random);
    ba += step_ba * Normal3(&random);
  }
  if (config.position_rate > 0.0) {
    const int64_t num_fixes = static_cast<int64_t>(std::floor(
                                  config.duration * config.position_rate)) +
                              1;
    for (int64_t m = 0; m < num_fixes; ++m) {
      PositionFix fix;
      fix.stamp = static_cast<TimeNs>(
          std::llround(static_cast<double>(m) * 1e9 / config.position_rate));
      const TrajectorySample s = trajectory.Evaluate(NsToSeconds(fix.stamp));
      fix.position =
          s.pose * config.lever_arm + config.position_sigma * Normal3(&random);
      out.positions.push_back(fix);
    }
  }
  const TrajectorySample s0 = trajectory.Evaluate(0.0);
  out.has_initial_state = true;
  out.initial_state.pose = s0.pose;
  out.initial_state.velocity = s0.velocity;
  *data = std::move(out);
  return true;
}

}  // namespace slam
