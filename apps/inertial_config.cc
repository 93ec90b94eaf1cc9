#include "apps/inertial_config.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "apps/yaml_config.h"

namespace slam {
namespace {

bool ReadVector3(const YAML::Node& node, const char* key,
                 const std::string& where, Eigen::Vector3d* value,
                 std::string* error) {
  std::vector<double> v;
  if (!ReadOptional(node, key, where, &v, error)) return false;
  if (!node[key]) return true;
  if (v.size() != 3) {
    *error = where + ": inertial." + key + " must be a list of 3 numbers";
    return false;
  }
  *value = Eigen::Vector3d(v[0], v[1], v[2]);
  return true;
}

std::string Vector3Yaml(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(17);
  out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return out.str();
}

}  // namespace

bool LoadInertialConfig(const std::string& path, InertialConfig* config,
                        std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["inertial"];
  if (!node) return true;
  if (!CheckKnownKeys(node,
                      {"input_format",
                       "initial_state",
                       "estimator",
                       "keyframe_rate",
                       "window_size",
                       "window_iterations",
                       "linear_solver",
                       "gravity",
                       "gyro_noise_density",
                       "accel_noise_density",
                       "gyro_random_walk",
                       "accel_random_walk",
                       "position_sigma",
                       "lever_arm",
                       "prior_position_sigma",
                       "prior_rotation_sigma",
                       "prior_velocity_sigma",
                       "prior_gyro_bias_sigma",
                       "prior_accel_bias_sigma",
                       "moving_start_gyro_bias_sigma",
                       "initial_gyro_bias",
                       "initial_accel_bias",
                       "gyro_noise_inflation",
                       "accel_noise_inflation"},
                      path, error)) {
    return false;
  }
  InertialOptions& o = config->options;
  if (!ReadOptional(node, "input_format", path, &config->input_format, error) ||
      !ReadOptional(node, "initial_state", path, &config->initial_state,
                    error) ||
      !ReadOptional(node, "estimator", path, &config->estimator, error) ||
      !ReadOptional(node, "keyframe_rate", path, &o.keyframe_rate_hz, error) ||
      !ReadOptional(node, "window_size", path, &o.window.window_size, error) ||
      !ReadOptional(node, "window_iterations", path, &o.window.max_iterations,
                    error) ||
      !ReadOptional(node, "linear_solver", path, &o.window.linear_solver,
                    error) ||
      !ReadOptional(node, "gyro_noise_density", path,
                    &o.noise.gyro_noise_density, error) ||
      !ReadOptional(node, "accel_noise_density", path,
                    &o.noise.accel_noise_density, error) ||
      !ReadOptional(node, "gyro_random_walk", path, &o.noise.gyro_random_walk,
                    error) ||
      !ReadOptional(node, "accel_random_walk", path, &o.noise.accel_random_walk,
                    error) ||
      !ReadOptional(node, "gyro_noise_inflation", path,
                    &config->gyro_noise_inflation, error) ||
      !ReadOptional(node, "accel_noise_inflation", path,
                    &config->accel_noise_inflation, error) ||
      !ReadOptional(node, "position_sigma", path, &o.position_sigma, error) ||
      !ReadVector3(node, "lever_arm", path, &o.lever_arm, error) ||
      !ReadOptional(node, "prior_position_sigma", path, &o.prior_position_sigma,
                    error) ||
      !ReadOptional(node, "prior_rotation_sigma", path, &o.prior_rotation_sigma,
                    error) ||
      !ReadOptional(node, "prior_velocity_sigma", path, &o.prior_velocity_sigma,
                    error) ||
      !ReadOptional(node, "prior_gyro_bias_sigma", path,
                    &o.prior_gyro_bias_sigma, error) ||
      !ReadOptional(node, "prior_accel_bias_sigma", path,
                    &o.prior_accel_bias_sigma, error) ||
      !ReadOptional(node, "moving_start_gyro_bias_sigma", path,
                    &o.moving_start_gyro_bias_sigma, error)) {
    return false;
  }
  Eigen::Vector3d gyro_bias = o.initial_bias.head<3>();
  Eigen::Vector3d accel_bias = o.initial_bias.tail<3>();
  if (!ReadVector3(node, "initial_gyro_bias", path, &gyro_bias, error) ||
      !ReadVector3(node, "initial_accel_bias", path, &accel_bias, error)) {
    return false;
  }
  o.initial_bias << gyro_bias, accel_bias;
  const YAML::Node gravity = node["gravity"];
  if (gravity) {
    if (gravity.IsScalar() && gravity.as<std::string>() == "auto") {
      config->gravity_auto = true;
    } else {
      if (!ReadVector3(node, "gravity", path, &o.gravity, error)) {
        *error = path + ": inertial.gravity must be auto or [gx, gy, gz]";
        return false;
      }
      config->gravity_auto = false;
    }
  }
  if (!ValidateInertialConfig(*config, error)) {
    *error = path + ": inertial." + *error;
    return false;
  }
  return true;
}

bool ValidateInertialConfig(const InertialConfig& config, std::string* error) {
  const InertialOptions& o = config.options;
  if (config.input_format != "auto" && config.input_format != "euroc" &&
      config.input_format != "gtsam") {
    *error = "input_format '" + config.input_format +
             "' is not one of auto, euroc, gtsam";
    return false;
  }
  if (config.initial_state != "auto" &&
      config.initial_state != "ground_truth") {
    *error = "initial_state '" + config.initial_state +
             "' is not one of auto, ground_truth";
    return false;
  }
  if (config.estimator != "window" && config.estimator != "batch" &&
      config.estimator != "both") {
    *error = "estimator '" + config.estimator +
             "' is not one of window, batch, both";
    return false;
  }
  if (!(o.keyframe_rate_hz > 0.0) || !std::isfinite(o.keyframe_rate_hz)) {
    *error = "keyframe_rate must be > 0";
    return false;
  }
  if (o.window.window_size < 2) {
    *error = "window_size must be >= 2";
    return false;
  }
  if (o.window.max_iterations < 1) {
    *error = "window_iterations must be >= 1";
    return false;
  }
  const std::string& s = o.window.linear_solver;
  if (s != "dense_normal_cholesky" && s != "dense_qr" && s != "dense_schur" &&
      s != "sparse_normal_cholesky") {
    *error = "linear_solver '" + s +
             "' is not one of dense_normal_cholesky, dense_qr, dense_schur, "
             "sparse_normal_cholesky";
    return false;
  }
  if (!o.noise.IsValid()) {
    *error = "noise densities and random walks must be > 0";
    return false;
  }
  for (double f : {config.gyro_noise_inflation, config.accel_noise_inflation}) {
    if (!(f > 0.0) || !std::isfinite(f)) {
      *error = "noise inflations must be > 0";
      return false;
    }
  }
  for (double sigma :
       {o.position_sigma, o.prior_position_sigma, o.prior_rotation_sigma,
        o.prior_velocity_sigma, o.prior_gyro_bias_sigma,
        o.prior_accel_bias_sigma, o.moving_start_gyro_bias_sigma}) {
    if (!(sigma > 0.0) || !std::isfinite(sigma)) {
      *error = "sigmas must be > 0";
      return false;
    }
  }
  if (!o.gravity.allFinite() || !o.lever_arm.allFinite() ||
      !o.initial_bias.allFinite()) {
    *error = "gravity, lever_arm and the initial biases must be finite";
    return false;
  }
  return true;
}

std::string InertialConfigToYaml(const InertialConfig& config) {
  const InertialOptions& o = config.options;
  std::ostringstream out;
  out.precision(17);
  out << "inertial:\n"
      << "  input_format: " << config.input_format << "\n"
      << "  initial_state: " << config.initial_state << "\n"
      << "  estimator: " << config.estimator << "\n"
      << "  keyframe_rate: " << o.keyframe_rate_hz << "\n"
      << "  window_size: " << o.window.window_size << "\n"
      << "  window_iterations: " << o.window.max_iterations << "\n"
      << "  linear_solver: " << o.window.linear_solver << "\n"
      << "  gravity: "
      << (config.gravity_auto ? std::string("auto") : Vector3Yaml(o.gravity))
      << "\n"
      << "  gyro_noise_density: " << o.noise.gyro_noise_density << "\n"
      << "  accel_noise_density: " << o.noise.accel_noise_density << "\n"
      << "  gyro_random_walk: " << o.noise.gyro_random_walk << "\n"
      << "  accel_random_walk: " << o.noise.accel_random_walk << "\n"
      << "  gyro_noise_inflation: " << config.gyro_noise_inflation << "\n"
      << "  accel_noise_inflation: " << config.accel_noise_inflation << "\n"
      << "  position_sigma: " << o.position_sigma << "\n"
      << "  lever_arm: " << Vector3Yaml(o.lever_arm) << "\n"
      << "  prior_position_sigma: " << o.prior_position_sigma << "\n"
      << "  prior_rotation_sigma: " << o.prior_rotation_sigma << "\n"
      << "  prior_velocity_sigma: " << o.prior_velocity_sigma << "\n"
      << "  prior_gyro_bias_sigma: " << o.prior_gyro_bias_sigma << "\n"
      << "  prior_accel_bias_sigma: " << o.prior_accel_bias_sigma << "\n"
      << "  moving_start_gyro_bias_sigma: " << o.moving_start_gyro_bias_sigma
      << "\n"
      << "  initial_gyro_bias: " << Vector3Yaml(o.initial_bias.head<3>())
      << "\n"
      << "  initial_accel_bias: " << Vector3Yaml(o.initial_bias.tail<3>())
      << "\n";
  return out.str();
}

InertialOptions EffectiveInertialOptions(const InertialConfig& config) {
  InertialOptions o = config.options;
  o.noise.gyro_noise_density *= config.gyro_noise_inflation;
  o.noise.accel_noise_density *= config.accel_noise_inflation;
  return o;
}

}  // namespace slam
