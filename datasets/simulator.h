// Synthetic pose-graph datasets with ground truth.
//
// Worlds (SimulationConfig::World::type):
//   grid2d    A robot on a square lattice (a Manhattan world, like the M3500
//             generator): at every move it goes one step straight ahead or
//             turns left/right by 90 degrees and steps, never leaving the
//             grid_size x grid_size lattice. SE(2) poses.
//   grid3d    The same on a grid_size^3 lattice: the robot's x axis points
//             along its motion and every turn is a 90-degree rotation about
//             an axis perpendicular to it, so roll, pitch and yaw all occur.
//             SE(3) poses.
//   sphere3d  A spiral on a sphere (like sphere2500): poses_per_ring poses
//             per revolution, climbing from the south to the north pole;
//             x axis along the motion, z axis along the outward normal.
//             SE(3) poses.
//   The trajectory is expressed in the frame of its first pose, so pose 0 is
//   the identity; it is fixed (Node::fixed), the gauge of the problem.
//
// Measurements (between factors, keys {older, newer}):
//   odometry       X_k -> X_{k+1} for every k.
//   loop closures  grid worlds: pose k to earlier poses j <= k - min_index_gap
//                  whose true position lies within `radius` (at most
//                  max_per_pose, chosen at random, each pose with chance
//                  `probability`); sphere3d: pose k to pose k -
//                  poses_per_ring (the previous ring), with chance
//                  `probability`.
//   outliers       outlier_fraction of all loop closures are wrong: random
//                  pairs of poses (not consecutive) with a random relative
//                  pose (translation uniform in [-a, a] per axis with a =
//                  outlier_max_translation, rotation uniform), carrying the
//                  loop-closure information.
//   The factors are added in time order (a factor at the time of its newer
//   pose, odometry first), as a logging robot would write them.
//
// Noise: sigma_translation in metres per axis; sigma_rotation in radians,
// FULL angle (core/conventions.h), per axis. The noise is sampled exactly in
// the error space of the between factors, so that the error of the true
// poses under a measurement, e = t2v(Z^-1 X_i^-1 X_j), is a draw from
// N(0, Omega^-1) and the chi2 of the ground truth is chi2-distributed with
// (residual dimensions) degrees of freedom:
//   SE(2)  e = (ex, ey, etheta) ~ N(0, diag(st^2, st^2, sr^2)),
//          Omega = diag(1/st^2, 1/st^2, 1/sr^2).
//   SE(3)  e = (t, qvec): t ~ N(0, st^2 I); the g2o rotation error is the
//          quaternion vector, about HALF the angle, so qvec ~ N(0, sr^2/4 I)
//          (the rotation angle 2 asin|qvec| is, to first order, a full-angle
//          N(0, sr^2) per axis) and Omega = diag(1/st^2 I, 4/sr^2 I).
//   A measurement is Z = X_i^-1 X_j v2t(e)^-1, i.e. the noise is applied on
//   the right (body frame).
//
// Initial values: dead reckoning, X_0 = I and X_{k+1} = X_k Z_{k,k+1} with
// the noisy odometry. Node stamps: k seconds.
//
// Randomness: one std::mt19937_64 seeded with `seed`; uniform and normal
// draws are computed from its raw output (not with the implementation-defined
// std:: distributions), so a seed gives the same dataset on every platform.
#ifndef SLAM_DATASETS_SIMULATOR_H_
#define SLAM_DATASETS_SIMULATOR_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/graph.h"
#include "core/keys.h"
#include "core/trajectory.h"

namespace slam {

struct SimulationConfig {
  struct World {
    std::string type = "grid2d";  // grid2d | grid3d | sphere3d.
    int num_poses = 500;
    // Grid worlds.
    double step = 1.0;             // Lattice spacing = length of a move [m].
    int grid_size = 10;            // Lattice points per side.
    double turn_probability = 0.3;  // Chance to turn at a move.
    // sphere3d.
    int poses_per_ring = 50;  // Poses per revolution of the spiral.
    double radius = 20.0;     // Sphere radius [m].
  };
  struct Noise {
    double sigma_translation = 0.05;  // [m], per axis.
    double sigma_rotation = 0.01;     // [rad], full angle, per axis.
  };
  struct LoopClosures {
    Noise noise;
    double radius = 0.5;       // Grid worlds: revisit distance [m].
    double probability = 0.8;  // Chance that a pose closes its loops.
    int max_per_pose = 1;      // Grid worlds.
    int min_index_gap = 5;     // Never close to the last few poses (>= 2).
    double outlier_fraction = 0.0;          // Share of all loop closures.
    double outlier_max_translation = 10.0;  // [m].
  };

  uint64_t seed = 1;
  World world;
  Noise odometry;
  LoopClosures loop_closures;
};

struct SimulationResult {
  // Nodes: Pose2Key(k) (grid2d) or Pose3Key(k), k = 0..num_poses-1, valued
  // by dead reckoning, node 0 fixed at the identity. Factors: the noisy
  // between measurements with information = inverse noise covariance (g2o's
  // convention, see above).
  Graph graph;
  bool is_3d = false;
  // True node values in node storage form (Pose2Value / Pose3Value).
  std::map<Key, std::vector<double>> ground_truth;
  // The true poses, stamp k seconds (2D lifted with LiftPose2).
  Trajectory ground_truth_trajectory;
  // Factor ids by role (odometry in time order; loop_closure_factors holds
  // every loop closure, the outliers included).
  std::vector<FactorId> odometry_factors;
  std::vector<FactorId> loop_closure_factors;
  std::vector<FactorId> outlier_factors;
};

// The world types Simulate knows, e.g. for help texts.
const std::vector<std::string>& SimulationWorldTypes();

// Checks names and ranges; false with a message naming the setting.
bool ValidateSimulationConfig(const SimulationConfig& config,
                              std::string* error);

// Generates a dataset into *result (overwritten). Deterministic for a given
// config. Returns false with *error if the config is invalid.
bool Simulate(const SimulationConfig& config, SimulationResult* result,
              std::string* error);

// Sets the graph's node values to `values` (keys absent from the graph are
// ignored); e.g. to the ground truth, to evaluate or write it.
void SetNodeValues(const std::map<Key, std::vector<double>>& values,
                   Graph* graph);

}  // namespace slam

#endif  // SLAM_DATASETS_SIMULATOR_H_
