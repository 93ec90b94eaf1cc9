// slam simulate: write a synthetic pose-graph or landmark dataset with ground
// truth (datasets/simulator.h) into a directory:
//
//   DIR/graph.g2o          noisy measurements; vertices = dead reckoning
//                          (landmark worlds: landmark vertices initialized
//                          from their first observations, factors with the
//                          landmark tags of datasets/g2o_io.h)
//   DIR/ground_truth.g2o   the same edges; vertices = the true poses (and
//                          landmarks)
//   DIR/landmarks.txt      landmark worlds: the true landmarks, one per line
//                          "id x y" (2D) or "id x y z" (3D), id = the g2o
//                          vertex id (a landmarks.txt left by an earlier
//                          pose-graph run is removed)
//   DIR/ground_truth.tum   true trajectory, "t x y z qx qy qz qw" (t = index
//                          in seconds; 2D poses lifted to z = 0)
//   DIR/outliers.txt       the outlier loop closures, if any: one line per
//                          edge, "edge_index from_id to_id", edge_index being
//                          the 0-based position among the EDGE lines of the
//                          .g2o files (an outliers.txt left by an earlier run
//                          without outliers is removed)
//
// World type inertial (datasets/inertial_simulator.h) writes instead an
// EuRoC-format folder (datasets/imu_io.h):
//   DIR/mav0/imu0/data.csv                        IMU readings
//   DIR/mav0/state_groundtruth_estimate0/data.csv ground truth p, q, v, biases
//   DIR/mav0/leica0/data.csv                      position fixes (if any)
//   DIR/ground_truth.tum                          the true trajectory
//
// Settings: defaults < --config FILE (the `simulate:` section, see
// apps/simulate_config.h and configs/simulate_*.yaml) < explicit flags.
// --dump_config prints the effective settings as YAML and exits.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/format.h"
#include "apps/simulate_config.h"
#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/imu_io.h"
#include "datasets/inertial_simulator.h"
#include "datasets/simulator.h"
#include "datasets/trajectory_io.h"

// The output path; defined by the optimize command (apps/optimize_command.cc).
DECLARE_string(o);

DEFINE_string(world, ::slam::SimulationConfig().world.type.c_str(),
              "simulate: world type, grid2d | grid3d | sphere3d | "
              "landmarks2d | landmarks3d | stereo | monocular | inertial");
DEFINE_int32(num_landmarks, ::slam::SimulationConfig().landmarks.num_landmarks,
             "simulate: landmark worlds: number of landmarks scattered");
DEFINE_int32(num_poses, ::slam::SimulationConfig().world.num_poses,
             "simulate: number of poses");
DEFINE_uint64(seed, ::slam::SimulationConfig().seed,
              "simulate: random seed (a seed gives the same dataset)");
DEFINE_double(outlier_fraction,
              ::slam::SimulationConfig().loop_closures.outlier_fraction,
              "simulate: share of loop closures that are wrong, [0, 1)");
DEFINE_double(odometry_sigma_t,
              ::slam::SimulationConfig().odometry.sigma_translation,
              "simulate: odometry noise, translation per axis [m]");
DEFINE_double(odometry_sigma_r,
              ::slam::SimulationConfig().odometry.sigma_rotation,
              "simulate: odometry noise, rotation per axis [rad, full angle]");
DEFINE_double(loop_sigma_t,
              ::slam::SimulationConfig().loop_closures.noise.sigma_translation,
              "simulate: loop-closure noise, translation per axis [m]");
DEFINE_double(loop_sigma_r,
              ::slam::SimulationConfig().loop_closures.noise.sigma_rotation,
              "simulate: loop-closure noise, rotation per axis [rad]");
DEFINE_double(loop_probability,
              ::slam::SimulationConfig().loop_closures.probability,
              "simulate: chance that a pose closes its loops");

namespace slam {
namespace {

bool FlagGiven(const char* name) {
  return !gflags::GetCommandLineFlagInfoOrDie(name).is_default;
}

// defaults < --config < explicit flags; validated.
bool BuildConfig(SimulationConfig* config, std::string* error) {
  if (!FLAGS_config.empty() &&
      !LoadSimulationConfig(FLAGS_config, config, error)) {
    return false;
  }
  if (FlagGiven("world")) config->world.type = FLAGS_world;
  if (FlagGiven("num_poses")) config->world.num_poses = FLAGS_num_poses;
  if (FlagGiven("num_landmarks")) {
    config->landmarks.num_landmarks = FLAGS_num_landmarks;
  }
  if (FlagGiven("seed")) config->seed = FLAGS_seed;
  SimulationConfig::LoopClosures& lc = config->loop_closures;
  if (FlagGiven("outlier_fraction")) {
    lc.outlier_fraction = FLAGS_outlier_fraction;
  }
  if (FlagGiven("odometry_sigma_t")) {
    config->odometry.sigma_translation = FLAGS_odometry_sigma_t;
  }
  if (FlagGiven("odometry_sigma_r")) {
    config->odometry.sigma_rotation = FLAGS_odometry_sigma_r;
  }
  if (FlagGiven("loop_sigma_t")) {
    lc.noise.sigma_translation = FLAGS_loop_sigma_t;
  }
  if (FlagGiven("loop_sigma_r")) lc.noise.sigma_rotation = FLAGS_loop_sigma_r;
  if (FlagGiven("loop_probability")) lc.probability = FLAGS_loop_probability;
  return ValidateSimulationConfig(*config, error);
}

// One line per outlier edge: "edge_index from_id to_id".
std::string OutliersText(const SimulationResult& result) {
  std::string text =
      "# Outlier loop closures: edge_index from_id to_id (edge_index: "
      "0-based position among the EDGE lines of graph.g2o)\n";
  for (FactorId id : result.outlier_factors) {
    const Factor* f = result.graph.FindFactor(id);
    text += std::to_string(id) + " " + std::to_string(f->keys[0].id) + " " +
            std::to_string(f->keys[1].id) + "\n";
  }
  return text;
}

// One line per landmark: "id x y [z]" (true values, %.17g).
std::string LandmarksText(const SimulationResult& result) {
  std::string text = result.is_3d ? "# True landmarks: id x y z\n"
                                  : "# True landmarks: id x y\n";
  char buffer[64];
  for (const Key& key : result.landmarks) {
    text += std::to_string(key.id);
    for (double v : result.ground_truth.at(key)) {
      std::snprintf(buffer, sizeof(buffer), " %.17g", v);
      text += buffer;
    }
    text += "\n";
  }
  return text;
}

// Writes `text` to `path` when `write`, else removes a stale `path`; sets
// *removed when it did.
bool WriteOrRemove(bool write, const std::string& path, const std::string& text,
                   bool* removed, std::string* error) {
  *removed = false;
  if (write) return WriteFileAtomically(path, text, error);
  std::error_code ec;
  if (std::filesystem::exists(path)) {
    *removed = std::filesystem::remove(path, ec);
  }
  return true;
}

// chi2 of the graph's current values over the factors not in `skip`.
double Chi2Without(const Graph& graph, const std::vector<FactorId>& skip) {
  const std::set<FactorId> skipped(skip.begin(), skip.end());
  double sum = 0.0;
  for (const auto& [id, factor] : graph.factors()) {
    if (skipped.count(id) > 0) continue;
    double chi2 = 0.0;
    if (graph.FactorChi2(factor, &chi2)) sum += chi2;
  }
  return sum;
}

int Fail(const std::string& message, int code = 1) {
  std::cerr << "slam simulate: " << message << "\n";
  return code;
}

// Creates the output directory (and its parents) if needed.
bool MakeOutputDirectory(const std::string& path, std::string* error) {
  return CreateOutputFolder(path, error);
}

// World type inertial: IMU + position fixes into an EuRoC folder.
int RunInertialSimulation(const SimulationConfig& config,
                          const std::string& out_dir) {
  InertialSimulationConfig inertial = config.inertial;
  inertial.seed = config.seed;
  InertialData data;
  std::string error;
  if (!SimulateInertial(inertial, &data, &error)) return Fail(error);
  const std::filesystem::path dir(out_dir);
  if (!MakeOutputDirectory(out_dir, &error)) return Fail(error);
  Trajectory truth;
  truth.reserve(data.ground_truth.size());
  for (const InertialGroundTruth& g : data.ground_truth) {
    truth.push_back({g.stamp, g.pose});
  }
  const std::string tum_path = (dir / "ground_truth.tum").string();
  if (!WriteEurocInertial(out_dir, data, &error) ||
      !WriteTrajectory(tum_path, truth, TrajectoryFormat::kTum, &error)) {
    return Fail(error);
  }
  const ImuNoise& n = inertial.noise;
  std::printf(
      "simulated inertial world (seed %llu): %.6g s, %zu IMU samples "
      "at %g Hz, %zu position fixes at %g Hz\n",
      static_cast<unsigned long long>(config.seed),
      NsToSeconds(data.imu.back().stamp), data.imu.size(), inertial.imu_rate,
      data.positions.size(), inertial.position_rate);
  std::printf(
      "IMU noise densities: gyro %g rad/s/sqrt(Hz), accel %g "
      "m/s^2/sqrt(Hz); bias random walks: gyro %g rad/s^2/sqrt(Hz), "
      "accel %g m/s^3/sqrt(Hz); position sigma %g m\n",
      n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk,
      n.accel_random_walk, inertial.position_sigma);
  std::printf("wrote %s/mav0 (imu0, state_groundtruth_estimate0%s) and %s\n",
              out_dir.c_str(), data.positions.empty() ? "" : ", leica0",
              tum_path.c_str());
  return 0;
}

}  // namespace

int RunSimulateCommand(const std::vector<std::string>& args) {
  if (!args.empty()) {
    return Fail("unexpected argument '" + args[0] +
                    "'; usage: slam simulate -o DIR [--world ...] "
                    "[--num_poses N] [--num_landmarks N] [--seed S] "
                    "[--outlier_fraction F] "
                    "[--config FILE] [--dump_config]",
                2);
  }
  SimulationConfig config;
  std::string error;
  if (!BuildConfig(&config, &error)) return Fail(error, 2);
  if (FLAGS_dump_config) {
    std::cout << SimulationConfigToYaml(config);
    return 0;
  }
  if (FLAGS_o.empty()) {
    return Fail("no output directory; usage: slam simulate -o DIR", 2);
  }

  if (config.world.type == "inertial") {
    return RunInertialSimulation(config, FLAGS_o);
  }

  SimulationResult result;
  if (!Simulate(config, &result, &error)) return Fail(error);

  // Write.
  const std::filesystem::path dir(FLAGS_o);
  if (!MakeOutputDirectory(FLAGS_o, &error)) return Fail(error);
  std::error_code ec;
  const std::string graph_path = (dir / "graph.g2o").string();
  const std::string truth_path = (dir / "ground_truth.g2o").string();
  const std::string tum_path = (dir / "ground_truth.tum").string();
  const std::string outliers_path = (dir / "outliers.txt").string();
  const std::string landmarks_path = (dir / "landmarks.txt").string();
  const double initial_chi2 = result.graph.Chi2();
  if (!WriteG2o(graph_path, result.graph, &error)) return Fail(error);
  SetNodeValues(result.ground_truth, &result.graph);
  const double truth_chi2 = result.graph.Chi2();
  const double truth_inlier_chi2 =
      Chi2Without(result.graph, result.outlier_factors);
  if (!WriteG2o(truth_path, result.graph, &error) ||
      !WriteTrajectory(tum_path, result.ground_truth_trajectory,
                       TrajectoryFormat::kTum, &error)) {
    return Fail(error);
  }
  bool removed_stale_outliers = false;
  bool removed_stale_landmarks = false;
  const bool has_landmarks = !result.landmarks.empty();
  if (!WriteOrRemove(!result.outlier_factors.empty(), outliers_path,
                     result.outlier_factors.empty() ? "" : OutliersText(result),
                     &removed_stale_outliers, &error) ||
      !WriteOrRemove(has_landmarks, landmarks_path,
                     has_landmarks ? LandmarksText(result) : "",
                     &removed_stale_landmarks, &error)) {
    return Fail(error);
  }

  // Summary.
  const size_t num_outliers = result.outlier_factors.size();
  const int dim = result.is_3d ? 6 : 3;
  // Residual dimensions of the inlier factors.
  const double dof = static_cast<double>(result.residual_dimensions -
                                         dim * static_cast<int>(num_outliers));
  const size_t num_poses = result.graph.NumNodes() - result.landmarks.size();
  if (has_landmarks) {
    const SimulationConfig::Landmarks& lm = config.landmarks;
    std::printf(
        "simulated %s world (seed %llu): %zu poses, %zu landmarks, "
        "%zu odometry, %zu landmark observations\n",
        config.world.type.c_str(), static_cast<unsigned long long>(config.seed),
        num_poses, result.landmarks.size(), result.odometry_factors.size(),
        result.landmark_factors.size());
    const std::string& type = config.world.type;
    std::string sensor;
    if (type == "stereo" || type == "monocular") {
      sensor = "pixel " + Fmt("%g", lm.sigma_pixel) + " px";
    } else if (type == "landmarks3d" || lm.observations != "range_bearing") {
      sensor = "position " + Fmt("%g", lm.sigma_position) + " m";
    }
    if (type == "landmarks2d" && lm.observations != "relative_position") {
      sensor = "range " + Fmt("%g", lm.sigma_range) + " m, bearing " +
               Fmt("%g", lm.sigma_bearing) + " rad" +
               (sensor.empty() ? "" : ", " + sensor);
    }
    std::printf(
        "noise (1 sigma per axis; rotation full angle): odometry %g m, %g "
        "rad%s; %s\n",
        config.odometry.sigma_translation, config.odometry.sigma_rotation,
        lm.odometry ? "" : " (initial guess only)", sensor.c_str());
    if (result.reinitialized_landmarks > 0) {
      std::printf(
          "%d landmark initial values placed again (the first "
          "lay behind a camera)\n",
          result.reinitialized_landmarks);
    }
  } else {
    std::printf(
        "simulated %s world (seed %llu): %zu poses, %zu odometry, "
        "%zu loop closures (%zu outliers)\n",
        config.world.type.c_str(), static_cast<unsigned long long>(config.seed),
        num_poses, result.odometry_factors.size(),
        result.loop_closure_factors.size(), num_outliers);
    std::printf(
        "noise (1 sigma per axis; rotation full angle): odometry "
        "%g m, %g rad; loop closures %g m, %g rad\n",
        config.odometry.sigma_translation, config.odometry.sigma_rotation,
        config.loop_closures.noise.sigma_translation,
        config.loop_closures.noise.sigma_rotation);
  }
  std::printf("chi2 of the initial guess (dead reckoning): %.10g\n",
              initial_chi2);
  std::printf(
      "chi2 of the ground truth: %.10g; without the outliers %.10g "
      "(expected %.0f +- %.0f)\n",
      truth_chi2, truth_inlier_chi2, dof, std::sqrt(2.0 * dof));
  const double optimum_dof = dof - result.free_dimensions;
  std::printf(
      "chi2 expected at the optimum: %.0f +- %.0f (%d free "
      "dimensions)\n",
      optimum_dof, std::sqrt(2.0 * std::max(optimum_dof, 0.0)),
      result.free_dimensions);
  std::printf("wrote %s, %s, %s", graph_path.c_str(), truth_path.c_str(),
              tum_path.c_str());
  if (num_outliers > 0) std::printf(", %s", outliers_path.c_str());
  if (has_landmarks) std::printf(", %s", landmarks_path.c_str());
  std::printf("\n");
  if (removed_stale_outliers) {
    std::printf("removed %s left by an earlier run\n", outliers_path.c_str());
  }
  if (removed_stale_landmarks) {
    std::printf("removed %s left by an earlier run\n", landmarks_path.c_str());
  }
  std::printf("next: slam optimize -i %s -o %s --gt %s\n", graph_path.c_str(),
              (dir / "optimized.g2o").string().c_str(), tum_path.c_str());
  return 0;
}

}  // namespace slam
