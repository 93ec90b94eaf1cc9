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
// Landmark worlds (see "Landmark worlds" below): landmarks2d, landmarks3d,
// stereo, monocular.
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
// Landmark worlds. Odometry (between factors, noise `odometry`, sampled as
// above) plus observations of point landmarks; no pose-to-pose loop
// closures (the loop_closures section is ignored): loops are closed by
// re-observing landmarks.
//   landmarks2d  The grid2d trajectory (SE(2) poses) through a field of
//                num_landmarks 2D points, uniform over the bounding box of the
//                trajectory grown by `margin`. A pose observes every point
//                within max_range whose bearing is within +-field_of_view/2
//                of its x axis, by range-bearing (range, bearing = atan2(y, x)
//                of the point in the pose frame; sigma_range, sigma_bearing),
//                by relative position (the point in the pose frame, g2o's
//                EDGE_SE2_XY; sigma_position per axis) or both, as
//                landmarks.observations says.
//   landmarks3d  The grid3d trajectory (SE(3) poses) through a field of 3D
//                points (the bounding box grown by `margin`), observed by
//                relative position in the frame of a sensor mounted at
//                sensor_offset = T_body_sensor (g2o's EDGE_SE3_TRACKXYZ with
//                PARAMS_SE3OFFSET) within max_range; sigma_position per axis.
//   stereo,      Cameras on a horizontal circle of radius world.radius about
//   monocular    the origin (num_poses over one revolution, the loop closing
//                on the first frames' points), each looking at the centre:
//                pose = T_world_camera, camera frame x right, y down (world
//                -z), z forward (towards the origin). num_landmarks points
//                uniform in a ball of radius field_radius about the origin.
//                A camera sees a point with depth in [min_depth, max_depth]
//                that projects inside the width x height image (for stereo
//                in both images): stereo (uL, uR, v), monocular (u, v) with
//                the pinhole model and radial-tangential distortion (k1, k2,
//                p1, p2); sigma_pixel per coordinate.
//   Measurement noise is added to the true measurement, zero-mean normal
//   with the sigmas above, and the information is diag(1/sigma^2), so the
//   ground truth's chi2 is chi2-distributed with (residual dimensions)
//   degrees of freedom (to first order: bearings and pixels are exact, the
//   odometry as above). Landmarks seen fewer than min_observations times are
//   left out; monocular landmarks also need two views whose rays are at
//   least min_parallax apart.
//   Node ids: poses Pose2Key(k)/Pose3Key(k), k = 0..num_poses-1; landmarks
//   Point2Key/Point3Key(num_poses + j), j = 0, 1, ... in the order of the
//   kept landmarks: no landmark id equals a pose id, so the written files
//   also suit readers with one id space for all vertices (g2o itself).
//   Gauge: pose 0 fixed at its true value. With landmarks.odometry false the
//   graph holds no odometry factors (pure bundle adjustment; the noisy
//   odometry only seeds the initial guess); a monocular world then also
//   fixes pose 1 at its true value, removing the scale (7-dof gauge).
//   Initial values: poses by dead reckoning from the fixed pose(s); each
//   landmark from its first observation through its (dead-reckoned) pose:
//   range-bearing inversion, relative position, stereo triangulation;
//   monocular: the midpoint of the earliest pair of rays whose true angle is
//   at least min_parallax (cameras close in time, so little drift between
//   them; the landmark initialization's own first-and-widest pair joins the
//   first and last cameras of the circle, which have drifted apart). A point
//   that lands behind a camera that sees it (drift, or a small noisy stereo
//   disparity) is placed again from other observations: stereo, the single
//   observation with the largest disparity that works; monocular, the next
//   pair of rays that works.
//   Factors: odometry first, then the observations in pose order; within a
//   pose in landmark order.
//
// Randomness: one std::mt19937_64 seeded with `seed`; uniform and normal
// draws are computed from its raw output (not with the implementation-defined
// std:: distributions), so a seed gives the same dataset on every platform.
#ifndef SLAM_DATASETS_SIMULATOR_H_
#define SLAM_DATASETS_SIMULATOR_H_

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/graph.h"
#include "core/keys.h"
#include "core/trajectory.h"
#include "datasets/inertial_simulator.h"

namespace slam {

struct SimulationConfig {
  struct World {
    std::string type = "grid2d";  // grid2d | grid3d | sphere3d.
    int num_poses = 500;
    // Grid worlds.
    double step = 1.0;              // Lattice spacing = length of a move [m].
    int grid_size = 10;             // Lattice points per side.
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
    double radius = 0.5;            // Grid worlds: revisit distance [m].
    double probability = 0.8;       // Chance that a pose closes its loops.
    int max_per_pose = 1;           // Grid worlds.
    int min_index_gap = 5;          // Never close to the last few poses (>= 2).
    double outlier_fraction = 0.0;  // Share of all loop closures.
    double outlier_max_translation = 10.0;  // [m].
  };

  // Landmark worlds only (landmarks2d, landmarks3d, stereo, monocular).
  struct Landmarks {
    int num_landmarks = 200;
    double margin = 2.0;  // landmarks2d/3d: field beyond the trajectory [m].
    double field_radius = 5.0;  // stereo/monocular: ball radius [m].
    int min_observations = 2;   // Landmarks seen less often are left out.
    // landmarks2d: range_bearing | relative_position | both.
    std::string observations = "range_bearing";
    double max_range = 5.0;           // landmarks2d/3d [m].
    double field_of_view = 2 * M_PI;  // landmarks2d: full opening [rad].
    double sigma_range = 0.05;        // [m].
    double sigma_bearing = 0.01;      // [rad].
    double sigma_position = 0.05;     // Relative position, per axis [m].
    double sigma_pixel = 1.0;         // Cameras, per coordinate [px].
    double min_parallax = 0.05;       // monocular: ray angle [rad].
    // landmarks3d: T_body_sensor, x y z qx qy qz qw.
    std::vector<double> sensor_offset = {0, 0, 0, 0, 0, 0, 1};
    bool odometry = true;  // Add the odometry factors to the graph.
  };
  // stereo and monocular: rectified pinhole cameras.
  struct Camera {
    double fx = 400.0, fy = 400.0, cx = 320.0, cy = 240.0;  // [px].
    int width = 640, height = 480;                          // [px].
    double baseline = 0.5;  // stereo: right camera at +baseline along x [m].
    double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0;  // monocular: radtan.
    double min_depth = 0.5, max_depth = 50.0;       // [m].
  };

  uint64_t seed = 1;
  World world;
  Noise odometry;
  LoopClosures loop_closures;
  Landmarks landmarks;
  Camera camera;
  // world.type "inertial": IMU and position fixes instead of a pose graph,
  // generated by SimulateInertial (datasets/inertial_simulator.h; its own
  // seed field is replaced by `seed`).
  InertialSimulationConfig inertial;
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
  // Landmark worlds: the observation factors, and the kept landmarks' keys
  // (their true values are in ground_truth).
  std::vector<FactorId> landmark_factors;
  std::vector<Key> landmarks;
  // Landmarks whose first initial value lay behind a camera that sees it,
  // placed again (see "Initial values" above).
  int reinitialized_landmarks = 0;
  // Sum of the factors' residual dimensions, and of the tangent dimensions
  // of the free (not fixed) nodes: after optimization chi2 is about
  // chi2-distributed with residual_dimensions - free_dimensions degrees of
  // freedom; the ground truth's with residual_dimensions.
  int residual_dimensions = 0;
  int free_dimensions = 0;
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
