#include "apps/simulate_config.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include <Eigen/Core>

#include "apps/yaml_config.h"
#include "apps/yaml_writer.h"

namespace slam {
namespace {

bool ReadNoise(const YAML::Node& node, const std::string& where,
               SimulationConfig::Noise* noise, std::string* error) {
  return ReadOptional(node, "sigma_translation", where,
                      &noise->sigma_translation, error) &&
         ReadOptional(node, "sigma_rotation", where, &noise->sigma_rotation,
                      error);
}

bool ReadLandmarks(const YAML::Node& node, const std::string& where,
                   SimulationConfig::Landmarks* lm, std::string* error) {
  if (!node || node.IsNull()) return true;
  return CheckKnownKeys(
             node,
             {"num_landmarks", "margin", "field_radius", "min_observations",
              "observations", "max_range", "field_of_view", "sigma_range",
              "sigma_bearing", "sigma_position", "sigma_pixel", "min_parallax",
              "sensor_offset", "odometry"},
             where, error) &&
         ReadOptional(node, "num_landmarks", where, &lm->num_landmarks,
                      error) &&
         ReadOptional(node, "margin", where, &lm->margin, error) &&
         ReadOptional(node, "field_radius", where, &lm->field_radius, error) &&
         ReadOptional(node, "min_observations", where, &lm->min_observations,
                      error) &&
         ReadOptional(node, "observations", where, &lm->observations, error) &&
         ReadOptional(node, "max_range", where, &lm->max_range, error) &&
         ReadOptional(node, "field_of_view", where, &lm->field_of_view,
                      error) &&
         ReadOptional(node, "sigma_range", where, &lm->sigma_range, error) &&
         ReadOptional(node, "sigma_bearing", where, &lm->sigma_bearing,
                      error) &&
         ReadOptional(node, "sigma_position", where, &lm->sigma_position,
                      error) &&
         ReadOptional(node, "sigma_pixel", where, &lm->sigma_pixel, error) &&
         ReadOptional(node, "min_parallax", where, &lm->min_parallax, error) &&
         ReadOptional(node, "sensor_offset", where, &lm->sensor_offset,
                      error) &&
         ReadOptional(node, "odometry", where, &lm->odometry, error);
}

bool ReadCamera(const YAML::Node& node, const std::string& where,
                SimulationConfig::Camera* c, std::string* error) {
  if (!node || node.IsNull()) return true;
  return CheckKnownKeys(node,
                        {"fx", "fy", "cx", "cy", "width", "height", "baseline",
                         "k1", "k2", "p1", "p2", "min_depth", "max_depth"},
                        where, error) &&
         ReadOptional(node, "fx", where, &c->fx, error) &&
         ReadOptional(node, "fy", where, &c->fy, error) &&
         ReadOptional(node, "cx", where, &c->cx, error) &&
         ReadOptional(node, "cy", where, &c->cy, error) &&
         ReadOptional(node, "width", where, &c->width, error) &&
         ReadOptional(node, "height", where, &c->height, error) &&
         ReadOptional(node, "baseline", where, &c->baseline, error) &&
         ReadOptional(node, "k1", where, &c->k1, error) &&
         ReadOptional(node, "k2", where, &c->k2, error) &&
         ReadOptional(node, "p1", where, &c->p1, error) &&
         ReadOptional(node, "p2", where, &c->p2, error) &&
         ReadOptional(node, "min_depth", where, &c->min_depth, error) &&
         ReadOptional(node, "max_depth", where, &c->max_depth, error);
}

// node[key] as a 3-vector [x, y, z] when present.
bool ReadVector3(const YAML::Node& node, const char* key,
                 const std::string& where, Eigen::Vector3d* value,
                 std::string* error) {
  std::vector<double> v;
  if (!ReadOptional(node, key, where, &v, error)) return false;
  if (!node[key]) return true;
  if (v.size() != 3) {
    *error = where + ": key '" + key + "' (line " +
             std::to_string(node[key].Mark().line + 1) +
             ") needs three numbers [x, y, z]";
    return false;
  }
  *value = Eigen::Vector3d(v[0], v[1], v[2]);
  return true;
}

// The `inertial:` sub-section (world type inertial).
bool ReadInertial(const YAML::Node& node, const std::string& where,
                  InertialSimulationConfig* c, std::string* error) {
  if (!CheckKnownKeys(
          node,
          {"duration", "imu_rate", "position_rate", "position_sigma",
           "lever_arm", "gravity", "gyro_noise_density", "accel_noise_density",
           "gyro_random_walk", "accel_random_walk", "initial_gyro_bias",
           "initial_accel_bias", "trajectory", "trajectory_file",
           "trajectory_times_file", "trajectory_y_down"},
          where, error) ||
      !ReadOptional(node, "duration", where, &c->duration, error) ||
      !ReadOptional(node, "imu_rate", where, &c->imu_rate, error) ||
      !ReadOptional(node, "position_rate", where, &c->position_rate, error) ||
      !ReadOptional(node, "position_sigma", where, &c->position_sigma, error) ||
      !ReadVector3(node, "lever_arm", where, &c->lever_arm, error) ||
      !ReadVector3(node, "gravity", where, &c->gravity, error) ||
      !ReadOptional(node, "gyro_noise_density", where,
                    &c->noise.gyro_noise_density, error) ||
      !ReadOptional(node, "accel_noise_density", where,
                    &c->noise.accel_noise_density, error) ||
      !ReadOptional(node, "gyro_random_walk", where, &c->noise.gyro_random_walk,
                    error) ||
      !ReadOptional(node, "accel_random_walk", where,
                    &c->noise.accel_random_walk, error) ||
      !ReadVector3(node, "initial_gyro_bias", where, &c->initial_gyro_bias,
                   error) ||
      !ReadVector3(node, "initial_accel_bias", where, &c->initial_accel_bias,
                   error) ||
      !ReadOptional(node, "trajectory_file", where, &c->trajectory_file,
                    error) ||
      !ReadOptional(node, "trajectory_times_file", where,
                    &c->trajectory_times_file, error) ||
      !ReadOptional(node, "trajectory_y_down", where, &c->trajectory_y_down,
                    error)) {
    return false;
  }
  const YAML::Node t = node["trajectory"];
  if (!t || t.IsNull()) return true;
  LissajousParams& p = c->trajectory;
  return CheckKnownKeys(t,
                        {"center", "amplitude", "frequency", "phase",
                         "yaw_rate", "yaw_amplitude", "yaw_frequency",
                         "pitch_amplitude", "pitch_frequency", "roll_amplitude",
                         "roll_frequency", "roll_phase"},
                        where, error) &&
         ReadVector3(t, "center", where, &p.center, error) &&
         ReadVector3(t, "amplitude", where, &p.amplitude, error) &&
         ReadVector3(t, "frequency", where, &p.frequency, error) &&
         ReadVector3(t, "phase", where, &p.phase, error) &&
         ReadOptional(t, "yaw_rate", where, &p.yaw_rate, error) &&
         ReadOptional(t, "yaw_amplitude", where, &p.yaw_amplitude, error) &&
         ReadOptional(t, "yaw_frequency", where, &p.yaw_frequency, error) &&
         ReadOptional(t, "pitch_amplitude", where, &p.pitch_amplitude, error) &&
         ReadOptional(t, "pitch_frequency", where, &p.pitch_frequency, error) &&
         ReadOptional(t, "roll_amplitude", where, &p.roll_amplitude, error) &&
         ReadOptional(t, "roll_frequency", where, &p.roll_frequency, error) &&
         ReadOptional(t, "roll_phase", where, &p.roll_phase, error);
}

}  // namespace

bool SimulationConfigFromYaml(const YAML::Node& root, const std::string& where,
                              SimulationConfig* config, std::string* error) {
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, where, error)) return false;
  const YAML::Node node = root["simulate"];
  if (!node || node.IsNull()) return true;
  if (!CheckKnownKeys(node,
                      {"seed", "world", "odometry", "loop_closures",
                       "landmarks", "camera", "inertial"},
                      where, error) ||
      !ReadOptional(node, "seed", where, &config->seed, error)) {
    return false;
  }
  const YAML::Node world = node["world"];
  if (world && !world.IsNull()) {
    SimulationConfig::World& w = config->world;
    if (!CheckKnownKeys(world,
                        {"type", "num_poses", "step", "grid_size",
                         "turn_probability", "poses_per_ring", "radius"},
                        where, error) ||
        !ReadOptional(world, "type", where, &w.type, error) ||
        !ReadOptional(world, "num_poses", where, &w.num_poses, error) ||
        !ReadOptional(world, "step", where, &w.step, error) ||
        !ReadOptional(world, "grid_size", where, &w.grid_size, error) ||
        !ReadOptional(world, "turn_probability", where, &w.turn_probability,
                      error) ||
        !ReadOptional(world, "poses_per_ring", where, &w.poses_per_ring,
                      error) ||
        !ReadOptional(world, "radius", where, &w.radius, error)) {
      return false;
    }
  }
  const YAML::Node odometry = node["odometry"];
  if (odometry && !odometry.IsNull()) {
    if (!CheckKnownKeys(odometry, {"sigma_translation", "sigma_rotation"},
                        where, error) ||
        !ReadNoise(odometry, where, &config->odometry, error)) {
      return false;
    }
  }
  const YAML::Node loops = node["loop_closures"];
  if (loops && !loops.IsNull()) {
    SimulationConfig::LoopClosures& lc = config->loop_closures;
    if (!CheckKnownKeys(loops,
                        {"sigma_translation", "sigma_rotation", "radius",
                         "probability", "max_per_pose", "min_index_gap",
                         "outlier_fraction", "outlier_max_translation"},
                        where, error) ||
        !ReadNoise(loops, where, &lc.noise, error) ||
        !ReadOptional(loops, "radius", where, &lc.radius, error) ||
        !ReadOptional(loops, "probability", where, &lc.probability, error) ||
        !ReadOptional(loops, "max_per_pose", where, &lc.max_per_pose, error) ||
        !ReadOptional(loops, "min_index_gap", where, &lc.min_index_gap,
                      error) ||
        !ReadOptional(loops, "outlier_fraction", where, &lc.outlier_fraction,
                      error) ||
        !ReadOptional(loops, "outlier_max_translation", where,
                      &lc.outlier_max_translation, error)) {
      return false;
    }
  }
  const YAML::Node inertial = node["inertial"];
  if (inertial && !inertial.IsNull() &&
      !ReadInertial(inertial, where, &config->inertial, error)) {
    return false;
  }
  return ReadLandmarks(node["landmarks"], where, &config->landmarks, error) &&
         ReadCamera(node["camera"], where, &config->camera, error);
}

bool LoadSimulationConfig(const std::string& path, SimulationConfig* config,
                          std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error) ||
      !SimulationConfigFromYaml(root, path, config, error)) {
    return false;
  }
  if (!ValidateSimulationConfig(*config, error)) {
    *error = path + ": simulate." + *error;
    return false;
  }
  return true;
}

std::string SimulationConfigToYaml(const SimulationConfig& config) {
  const SimulationConfig::World& w = config.world;
  const SimulationConfig::LoopClosures& lc = config.loop_closures;
  YamlWriter out;
  out.Section(0, "simulate");
  out.Value(2, "seed", config.seed);
  out.Section(2, "world");
  out.Value(4, "type", w.type,
            "grid2d | grid3d | sphere3d | landmarks2d | landmarks3d | "
            "stereo | monocular | inertial");
  out.Value(4, "num_poses", w.num_poses);
  out.Value(4, "step", w.step, "grid worlds: lattice spacing [m]");
  out.Value(4, "grid_size", w.grid_size,
            "grid worlds: lattice points per side");
  out.Value(4, "turn_probability", w.turn_probability,
            "grid worlds: chance to turn at a move");
  out.Value(4, "poses_per_ring", w.poses_per_ring,
            "sphere3d: poses per revolution");
  out.Value(4, "radius", w.radius,
            "sphere3d: sphere radius; stereo/monocular: circle [m]");
  out.Section(2, "odometry");
  out.Value(4, "sigma_translation", config.odometry.sigma_translation,
            "[m] per axis");
  out.Value(4, "sigma_rotation", config.odometry.sigma_rotation,
            "[rad] full angle, per axis");
  out.Section(2, "loop_closures");
  out.Value(4, "sigma_translation", lc.noise.sigma_translation, "[m] per axis");
  out.Value(4, "sigma_rotation", lc.noise.sigma_rotation,
            "[rad] full angle, per axis");
  out.Value(4, "radius", lc.radius, "grid worlds: revisit distance [m]");
  out.Value(4, "probability", lc.probability,
            "chance that a pose closes its loops");
  out.Value(4, "max_per_pose", lc.max_per_pose, "grid worlds");
  out.Value(4, "min_index_gap", lc.min_index_gap,
            "no closures to the last few poses");
  out.Value(4, "outlier_fraction", lc.outlier_fraction,
            "share of wrong loop closures, [0, 1)");
  out.Value(4, "outlier_max_translation", lc.outlier_max_translation,
            "outliers: translation range [m]");
  const SimulationConfig::Landmarks& lm = config.landmarks;
  out.Section(2, "landmarks", "landmarks2d | landmarks3d | stereo | monocular");
  out.Value(4, "num_landmarks", lm.num_landmarks);
  out.Value(4, "margin", lm.margin, "landmarks2d/3d: field beyond path [m]");
  out.Value(4, "field_radius", lm.field_radius,
            "stereo/monocular: point ball radius [m]");
  out.Value(4, "min_observations", lm.min_observations,
            "landmarks seen less often are left out");
  out.Value(4, "observations", lm.observations,
            "landmarks2d: range_bearing | relative_position | both");
  out.Value(4, "max_range", lm.max_range, "landmarks2d/3d: sensor range [m]");
  out.Value(4, "field_of_view", lm.field_of_view,
            "landmarks2d: full opening angle [rad]");
  out.Value(4, "sigma_range", lm.sigma_range, "[m]");
  out.Value(4, "sigma_bearing", lm.sigma_bearing, "[rad]");
  out.Value(4, "sigma_position", lm.sigma_position,
            "relative position, per axis [m]");
  out.Value(4, "sigma_pixel", lm.sigma_pixel, "cameras, per coordinate [px]");
  out.Value(4, "min_parallax", lm.min_parallax,
            "monocular: widest ray angle needed [rad]");
  out.Value(4, "sensor_offset", lm.sensor_offset,
            "landmarks3d: T_body_sensor x y z qx qy qz qw");
  out.Value(4, "odometry", lm.odometry, "false: no odometry factors (pure BA)");
  const SimulationConfig::Camera& c = config.camera;
  out.Section(2, "camera", "stereo | monocular");
  out.Value(4, "fx", c.fx, "[px]");
  out.Value(4, "fy", c.fy, "[px]");
  out.Value(4, "cx", c.cx, "[px]");
  out.Value(4, "cy", c.cy, "[px]");
  out.Value(4, "width", c.width, "[px]");
  out.Value(4, "height", c.height, "[px]");
  out.Value(4, "baseline", c.baseline, "stereo [m]");
  out.Value(4, "k1", c.k1, "monocular: radial-tangential distortion");
  out.Value(4, "k2", c.k2);
  out.Value(4, "p1", c.p1);
  out.Value(4, "p2", c.p2);
  out.Value(4, "min_depth", c.min_depth, "[m]");
  out.Value(4, "max_depth", c.max_depth, "[m]");
  const InertialSimulationConfig& in = config.inertial;
  out.Section(2, "inertial", "world type inertial");
  out.Value(4, "duration", in.duration, "[s]");
  out.Value(4, "imu_rate", in.imu_rate, "[Hz]");
  out.Value(4, "position_rate", in.position_rate, "[Hz], 0: no fixes");
  out.Value(4, "position_sigma", in.position_sigma, "[m] per axis");
  out.Value(4, "lever_arm", in.lever_arm, "antenna in the body frame [m]");
  out.Value(4, "gravity", in.gravity, "[m/s^2], world frame");
  out.Value(4, "gyro_noise_density", in.noise.gyro_noise_density,
            "[rad/s/sqrt(Hz)]");
  out.Value(4, "accel_noise_density", in.noise.accel_noise_density,
            "[m/s^2/sqrt(Hz)]");
  out.Value(4, "gyro_random_walk", in.noise.gyro_random_walk,
            "[rad/s^2/sqrt(Hz)]");
  out.Value(4, "accel_random_walk", in.noise.accel_random_walk,
            "[m/s^3/sqrt(Hz)]");
  out.Value(4, "initial_gyro_bias", in.initial_gyro_bias, "[rad/s]");
  out.Value(4, "initial_accel_bias", in.initial_accel_bias, "[m/s^2]");
  out.Value(4, "trajectory_file", Quoted(in.trajectory_file),
            "spline through this file instead of the curve below");
  out.Value(4, "trajectory_times_file", Quoted(in.trajectory_times_file),
            "KITTI: its times file");
  out.Value(4, "trajectory_y_down", in.trajectory_y_down,
            "the file's world has y down (KITTI)");
  const LissajousParams& p = in.trajectory;
  out.Section(4, "trajectory", "p = center + amplitude .* sin(f t + phase)");
  out.Value(6, "center", p.center, "[m]");
  out.Value(6, "amplitude", p.amplitude, "[m]");
  out.Value(6, "frequency", p.frequency, "[rad/s]");
  out.Value(6, "phase", p.phase, "[rad]");
  out.Value(6, "yaw_rate", p.yaw_rate, "[rad/s]");
  out.Value(6, "yaw_amplitude", p.yaw_amplitude, "[rad]");
  out.Value(6, "yaw_frequency", p.yaw_frequency, "[rad/s]");
  out.Value(6, "pitch_amplitude", p.pitch_amplitude, "[rad]");
  out.Value(6, "pitch_frequency", p.pitch_frequency, "[rad/s]");
  out.Value(6, "roll_amplitude", p.roll_amplitude, "[rad]");
  out.Value(6, "roll_frequency", p.roll_frequency, "[rad/s]");
  out.Value(6, "roll_phase", p.roll_phase, "[rad]");
  return out.str();
}

}  // namespace slam
