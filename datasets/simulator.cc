#include "datasets/simulator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"
#include "datasets/simulator_internal.h"
#include "factors/pose_factors.h"

namespace slam {

using simulator_internal::CheckPositive;
using simulator_internal::CheckProbability;
using simulator_internal::GridWorld2d;
using simulator_internal::GridWorld3d;
using simulator_internal::Information2;
using simulator_internal::Information3;
using simulator_internal::Random;
using simulator_internal::SampleNoise2;
using simulator_internal::SampleNoise3;
using simulator_internal::TruePoses;

namespace {

// ---------------------------------------------------------------------------
// Worlds.

bool Inside(const Eigen::Vector3i& cell, int grid_size, int dims) {
  for (int d = 0; d < dims; ++d) {
    if (cell[d] < 0 || cell[d] >= grid_size) return false;
  }
  return true;
}

// Picks the index of the next direction among `forward` (index 0) and the
// turns (indices 1..), given which are allowed; -1 if none is.
int ChooseMove(const std::vector<bool>& allowed, double turn_probability,
               Random* random) {
  std::vector<int> turns;
  for (size_t i = 1; i < allowed.size(); ++i) {
    if (allowed[i]) turns.push_back(static_cast<int>(i));
  }
  const bool want_turn = random->Bernoulli(turn_probability);
  if (allowed[0] && (!want_turn || turns.empty())) return 0;
  if (turns.empty()) return -1;
  return turns[random->UniformInt(static_cast<int64_t>(turns.size()))];
}

}  // namespace

namespace simulator_internal {

// grid2d: heading h in {0, 1, 2, 3} = +x, +y, -x, -y.
void GridWorld2d(const SimulationConfig::World& world, Random* random,
                 TruePoses* truth) {
  static const int kDx[4] = {1, 0, -1, 0};
  static const int kDy[4] = {0, 1, 0, -1};
  truth->is_3d = false;
  Eigen::Vector3i cell(0, 0, 0);
  int heading = 0;
  for (int k = 0; k < world.num_poses; ++k) {
    if (k > 0) {
      // Straight, left, right.
      const int candidates[3] = {heading, (heading + 1) % 4, (heading + 3) % 4};
      std::vector<bool> allowed(3);
      for (int c = 0; c < 3; ++c) {
        const int h = candidates[c];
        allowed[c] = Inside(cell + Eigen::Vector3i(kDx[h], kDy[h], 0),
                            world.grid_size, 2);
      }
      const int choice = ChooseMove(allowed, world.turn_probability, random);
      heading = choice < 0 ? (heading + 2) % 4 : candidates[choice];
      cell += Eigen::Vector3i(kDx[heading], kDy[heading], 0);
    }
    const Pose2 pose(world.step * cell.x(), world.step * cell.y(),
                     heading * M_PI / 2.0);
    truth->poses2.push_back(pose);
    truth->positions.emplace_back(pose.t.x(), pose.t.y(), 0.0);
  }
}

// grid3d: orientation R (columns: body axes in the world), axis-aligned; the
// body x axis is the direction of the last move.
void GridWorld3d(const SimulationConfig::World& world, Random* random,
                 TruePoses* truth) {
  truth->is_3d = true;
  Eigen::Vector3i cell(0, 0, 0);
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  for (int k = 0; k < world.num_poses; ++k) {
    if (k > 0) {
      const Eigen::Vector3d forward = rotation.col(0);
      const Eigen::Vector3d left = rotation.col(1);
      const Eigen::Vector3d up = rotation.col(2);
      // Straight, then the four 90-degree turns.
      const Eigen::Vector3d candidates[5] = {forward, left, -left, up, -up};
      std::vector<bool> allowed(5);
      for (int c = 0; c < 5; ++c) {
        const Eigen::Vector3i move =
            candidates[c].array().round().cast<int>().matrix();
        allowed[c] = Inside(cell + move, world.grid_size, 3);
      }
      const int choice = ChooseMove(allowed, world.turn_probability, random);
      Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();
      Eigen::Vector3d direction;
      if (choice < 0) {  // Dead end: turn around about the body z axis.
        turn = Eigen::AngleAxisd(M_PI, up).toRotationMatrix();
        direction = -forward;
      } else {
        direction = candidates[choice];
        if (choice > 0) {
          turn = Eigen::AngleAxisd(M_PI / 2.0, forward.cross(direction))
                     .toRotationMatrix();
        }
      }
      // Axis-aligned: round away the floating-point residue.
      rotation = (turn * rotation).array().round().matrix();
      cell += direction.array().round().cast<int>().matrix();
    }
    const Pose3 pose(world.step * cell.cast<double>(),
                     Eigen::Quaterniond(rotation));
    truth->poses3.push_back(pose);
    truth->positions.push_back(pose.t);
  }
}

}  // namespace simulator_internal

namespace {

// sphere3d: a spiral parameterized by s = pose index.
void SphereWorld(const SimulationConfig::World& world, TruePoses* truth) {
  truth->is_3d = true;
  const double n = world.num_poses;
  const double p = world.poses_per_ring;
  const double d_azimuth = 2.0 * M_PI / p;
  const double d_elevation = M_PI / (n + p);
  std::vector<Pose3> poses;
  for (int k = 0; k < world.num_poses; ++k) {
    const double azimuth = d_azimuth * k;
    const double elevation = -M_PI / 2.0 + d_elevation * (k + p / 2.0);
    const double ce = std::cos(elevation), se = std::sin(elevation);
    const double ca = std::cos(azimuth), sa = std::sin(azimuth);
    const Eigen::Vector3d up(ce * ca, ce * sa, se);
    const Eigen::Vector3d tangent =
        Eigen::Vector3d(-se * ca, -se * sa, ce) * d_elevation +
        Eigen::Vector3d(-ce * sa, ce * ca, 0.0) * d_azimuth;
    const Eigen::Vector3d forward = tangent.normalized();
    Eigen::Matrix3d rotation;
    rotation.col(0) = forward;
    rotation.col(1) = up.cross(forward);
    rotation.col(2) = up;
    poses.emplace_back(world.radius * up, Eigen::Quaterniond(rotation));
  }
  // Expressed in the frame of the first pose.
  const Pose3 origin_inv = poses.front().Inverse();
  for (const Pose3& pose : poses) {
    truth->poses3.push_back(origin_inv * pose);
    truth->positions.push_back(truth->poses3.back().t);
  }
}

// ---------------------------------------------------------------------------
// Loop closures.

struct Edge {
  int i = 0;  // Older pose.
  int j = 0;  // Newer pose.
  enum Kind { kOdometry, kLoopClosure, kOutlier } kind = kOdometry;
};

// Grid worlds: earlier poses within `radius` of the current one, found
// through a hash of cells of size max(radius, step).
void GridLoopClosures(const SimulationConfig& config, const TruePoses& truth,
                      Random* random, std::vector<Edge>* edges) {
  const SimulationConfig::LoopClosures& lc = config.loop_closures;
  const double cell_size = std::max(lc.radius, config.world.step);
  std::map<std::array<int64_t, 3>, std::vector<int>> buckets;
  auto bucket_of = [&](const Eigen::Vector3d& p) {
    return std::array<int64_t, 3>{
        static_cast<int64_t>(std::floor(p.x() / cell_size)),
        static_cast<int64_t>(std::floor(p.y() / cell_size)),
        static_cast<int64_t>(std::floor(p.z() / cell_size))};
  };
  const int n = truth.size();
  std::vector<int> candidates;
  for (int k = 0; k < n; ++k) {
    // Make poses old enough visible to the search.
    const int visible = k - lc.min_index_gap;
    if (visible >= 0) {
      buckets[bucket_of(truth.positions[visible])].push_back(visible);
    }
    candidates.clear();
    const std::array<int64_t, 3> b = bucket_of(truth.positions[k]);
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = buckets.find({b[0] + dx, b[1] + dy, b[2] + dz});
          if (it == buckets.end()) continue;
          for (int j : it->second) {
            if ((truth.positions[j] - truth.positions[k]).norm() <=
                lc.radius + 1e-9) {
              candidates.push_back(j);
            }
          }
        }
      }
    }
    if (candidates.empty() || !random->Bernoulli(lc.probability)) continue;
    // A random subset of max_per_pose candidates (partial Fisher-Yates).
    const int take =
        std::min<int>(lc.max_per_pose, static_cast<int>(candidates.size()));
    for (int t = 0; t < take; ++t) {
      const int pick = t + static_cast<int>(random->UniformInt(
                               static_cast<int64_t>(candidates.size()) - t));
      std::swap(candidates[t], candidates[pick]);
    }
    std::sort(candidates.begin(), candidates.begin() + take);
    for (int t = 0; t < take; ++t) {
      edges->push_back({candidates[t], k, Edge::kLoopClosure});
    }
  }
}

void SphereLoopClosures(const SimulationConfig& config, const TruePoses& truth,
                        Random* random, std::vector<Edge>* edges) {
  const int ring = config.world.poses_per_ring;
  for (int k = ring; k < truth.size(); ++k) {
    if (random->Bernoulli(config.loop_closures.probability)) {
      edges->push_back({k - ring, k, Edge::kLoopClosure});
    }
  }
}

void OutlierLoopClosures(const SimulationConfig& config, int num_poses,
                         int num_inliers, Random* random,
                         std::vector<Edge>* edges) {
  const double f = config.loop_closures.outlier_fraction;
  if (f <= 0.0 || num_poses < 3) return;
  const int count = static_cast<int>(std::llround(f / (1.0 - f) * num_inliers));
  for (int c = 0; c < count; ++c) {
    int a, b;
    do {
      a = static_cast<int>(random->UniformInt(num_poses));
      b = static_cast<int>(random->UniformInt(num_poses));
    } while (std::abs(a - b) < 2);
    edges->push_back({std::min(a, b), std::max(a, b), Edge::kOutlier});
  }
}

// ---------------------------------------------------------------------------
// Measurements.

}  // namespace

namespace simulator_internal {

// v2t(e)^-1 with e drawn from the between factor's error distribution.
Pose2 SampleNoise2(const SimulationConfig::Noise& noise, Random* random) {
  const double ex = noise.sigma_translation * random->Normal();
  const double ey = noise.sigma_translation * random->Normal();
  const double et = noise.sigma_rotation * random->Normal();
  return Pose2(ex, ey, et).Inverse();
}

Pose3 SampleNoise3(const SimulationConfig::Noise& noise, Random* random) {
  Eigen::Vector3d t, qvec;
  for (int a = 0; a < 3; ++a) t[a] = noise.sigma_translation * random->Normal();
  // The quaternion vector of the error, about half the angle. Draws outside
  // the unit ball (only for absurd sigmas) are redrawn.
  do {
    for (int a = 0; a < 3; ++a) {
      qvec[a] = 0.5 * noise.sigma_rotation * random->Normal();
    }
  } while (qvec.squaredNorm() >= 1.0);
  const Eigen::Quaterniond q(std::sqrt(1.0 - qvec.squaredNorm()), qvec.x(),
                             qvec.y(), qvec.z());
  return Pose3(t, q).Inverse();
}

Eigen::Matrix3d Information2(const SimulationConfig::Noise& noise) {
  const double it = 1.0 / (noise.sigma_translation * noise.sigma_translation);
  const double ir = 1.0 / (noise.sigma_rotation * noise.sigma_rotation);
  return Eigen::Vector3d(it, it, ir).asDiagonal();
}

Eigen::Matrix<double, 6, 6> Information3(const SimulationConfig::Noise& noise) {
  const double it = 1.0 / (noise.sigma_translation * noise.sigma_translation);
  const double ir = 4.0 / (noise.sigma_rotation * noise.sigma_rotation);
  Eigen::Matrix<double, 6, 1> d;
  d << it, it, it, ir, ir, ir;
  return d.asDiagonal();
}

bool CheckPositive(double value, const char* name, std::string* error) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    *error = std::string(name) + " must be a positive number";
    return false;
  }
  return true;
}

bool CheckProbability(double value, const char* name, std::string* error) {
  if (!(value >= 0.0 && value <= 1.0)) {
    *error = std::string(name) + " must be in [0, 1]";
    return false;
  }
  return true;
}

}  // namespace simulator_internal

namespace {

bool CheckNoise(const SimulationConfig::Noise& noise, const char* section,
                std::string* error) {
  const std::string t = std::string(section) + ".sigma_translation";
  const std::string r = std::string(section) + ".sigma_rotation";
  if (!CheckPositive(noise.sigma_translation, t.c_str(), error) ||
      !CheckPositive(noise.sigma_rotation, r.c_str(), error)) {
    return false;
  }
  if (noise.sigma_rotation > 1.0) {
    *error = r + " must be at most 1 rad";
    return false;
  }
  return true;
}

// Residual dimensions of all factors and tangent dimensions of the free
// nodes (SimulationResult).
void CountDimensions(SimulationResult* result) {
  result->residual_dimensions = 0;
  result->free_dimensions = 0;
  for (const auto& [id, factor] : result->graph.factors()) {
    result->residual_dimensions += factor.cost->num_residuals();
  }
  for (const auto& [key, node] : result->graph.nodes()) {
    if (!node->fixed) result->free_dimensions += TangentSize(key.kind);
  }
}

}  // namespace

const std::vector<std::string>& SimulationWorldTypes() {
  static const auto* types = new std::vector<std::string>{
      "grid2d",      "grid3d", "sphere3d",  "landmarks2d",
      "landmarks3d", "stereo", "monocular", "inertial"};
  return *types;
}

bool ValidateSimulationConfig(const SimulationConfig& config,
                              std::string* error) {
  const SimulationConfig::World& w = config.world;
  const auto& types = SimulationWorldTypes();
  if (std::find(types.begin(), types.end(), w.type) == types.end()) {
    std::string names;
    for (const std::string& name : types) {
      names += (names.empty() ? "" : ", ") + name;
    }
    *error = "world.type '" + w.type + "' is not one of " + names;
    return false;
  }
  if (w.type == "inertial") {
    return ValidateInertialSimulationConfig(config.inertial, error);
  }
  if (w.num_poses < 2 || w.num_poses > 10000000) {
    *error = "world.num_poses must be in [2, 10000000]";
    return false;
  }
  if (!CheckPositive(w.step, "world.step", error) ||
      !CheckPositive(w.radius, "world.radius", error) ||
      !CheckProbability(w.turn_probability, "world.turn_probability", error)) {
    return false;
  }
  if (w.grid_size < 2) {
    *error = "world.grid_size must be at least 2";
    return false;
  }
  if (w.poses_per_ring < 3) {
    *error = "world.poses_per_ring must be at least 3";
    return false;
  }
  if (!CheckNoise(config.odometry, "odometry", error) ||
      !CheckNoise(config.loop_closures.noise, "loop_closures", error)) {
    return false;
  }
  const SimulationConfig::LoopClosures& lc = config.loop_closures;
  if (!(lc.radius >= 0.0) || !std::isfinite(lc.radius)) {
    *error = "loop_closures.radius must be >= 0";
    return false;
  }
  if (!CheckProbability(lc.probability, "loop_closures.probability", error)) {
    return false;
  }
  if (lc.max_per_pose < 0) {
    *error = "loop_closures.max_per_pose must be >= 0";
    return false;
  }
  if (lc.min_index_gap < 2) {
    *error = "loop_closures.min_index_gap must be at least 2 (1 is odometry)";
    return false;
  }
  if (!(lc.outlier_fraction >= 0.0 && lc.outlier_fraction < 1.0)) {
    *error = "loop_closures.outlier_fraction must be in [0, 1)";
    return false;
  }
  return CheckPositive(lc.outlier_max_translation,
                       "loop_closures.outlier_max_translation", error) &&
         simulator_internal::ValidateLandmarkConfig(config, error);
}

bool Simulate(const SimulationConfig& config, SimulationResult* result,
              std::string* error) {
  if (!ValidateSimulationConfig(config, error)) return false;
  if (config.world.type == "inertial") {
    *error = "world.type inertial is simulated by SimulateInertial";
    return false;
  }
  *result = SimulationResult();
  Random random(config.seed);
  if (simulator_internal::IsLandmarkWorld(config.world.type)) {
    if (!simulator_internal::SimulateLandmarkWorld(config, &random, result,
                                                   error)) {
      return false;
    }
    CountDimensions(result);
    return true;
  }

  // 1. The true trajectory.
  TruePoses truth;
  const std::string& type = config.world.type;
  if (type == "grid2d") {
    GridWorld2d(config.world, &random, &truth);
  } else if (type == "grid3d") {
    GridWorld3d(config.world, &random, &truth);
  } else {
    SphereWorld(config.world, &truth);
  }
  const int n = truth.size();
  result->is_3d = truth.is_3d;

  // 2. Which measurements: odometry, loop closures, outliers; in time order.
  std::vector<Edge> edges;
  for (int k = 0; k + 1 < n; ++k) edges.push_back({k, k + 1, Edge::kOdometry});
  std::vector<Edge> closures;
  if (type == "sphere3d") {
    SphereLoopClosures(config, truth, &random, &closures);
  } else {
    GridLoopClosures(config, truth, &random, &closures);
  }
  const int num_inliers = static_cast<int>(closures.size());
  OutlierLoopClosures(config, n, num_inliers, &random, &closures);
  edges.insert(edges.end(), closures.begin(), closures.end());
  std::stable_sort(edges.begin(), edges.end(),
                   [](const Edge& a, const Edge& b) { return a.j < b.j; });

  // 3. The measurements, in factor order.
  std::vector<Pose2> z2(edges.size());
  std::vector<Pose3> z3(edges.size());
  const double a = config.loop_closures.outlier_max_translation;
  for (size_t e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    const SimulationConfig::Noise& noise = edge.kind == Edge::kOdometry
                                               ? config.odometry
                                               : config.loop_closures.noise;
    if (truth.is_3d) {
      if (edge.kind == Edge::kOutlier) {
        // One draw per statement (argument order is unspecified; z, y, x
        // is what gcc did, see ScatterLandmarks in landmark_simulator.cc).
        const double tz = random.Uniform(-a, a);
        const double ty = random.Uniform(-a, a);
        const double tx = random.Uniform(-a, a);
        const Eigen::Vector3d t(tx, ty, tz);
        z3[e] = Pose3(t, random.UniformRotation());
      } else {
        z3[e] = truth.poses3[edge.i].Inverse() * truth.poses3[edge.j] *
                SampleNoise3(noise, &random);
      }
    } else {
      if (edge.kind == Edge::kOutlier) {
        const double x = random.Uniform(-a, a);
        const double y = random.Uniform(-a, a);
        z2[e] = Pose2(x, y, random.Uniform(-M_PI, M_PI));
      } else {
        z2[e] = truth.poses2[edge.i].Inverse() * truth.poses2[edge.j] *
                SampleNoise2(noise, &random);
      }
    }
  }

  // 4. Nodes: dead reckoning along the noisy odometry.
  Graph& graph = result->graph;
  std::vector<Pose2> dr2(truth.is_3d ? 0 : n);
  std::vector<Pose3> dr3(truth.is_3d ? n : 0);
  for (size_t e = 0; e < edges.size(); ++e) {
    if (edges[e].kind != Edge::kOdometry) continue;
    const int k = edges[e].i;
    if (truth.is_3d) {
      dr3[k + 1] = dr3[k] * z3[e];
    } else {
      dr2[k + 1] = dr2[k] * z2[e];
    }
  }
  for (int k = 0; k < n; ++k) {
    const Key key = truth.is_3d ? Pose3Key(k) : Pose2Key(k);
    const std::vector<double> value =
        truth.is_3d ? Pose3Value(dr3[k]) : Pose2Value(dr2[k]);
    Node* node = graph.AddNode(key, value);
    node->stamp = static_cast<TimeNs>(k) * kNanosecondsPerSecond;
    node->has_stamp = true;
    node->fixed = (k == 0);
    const Pose3 true_pose =
        truth.is_3d ? truth.poses3[k] : LiftPose2(truth.poses2[k]);
    result->ground_truth[key] =
        truth.is_3d ? Pose3Value(truth.poses3[k]) : Pose2Value(truth.poses2[k]);
    result->ground_truth_trajectory.push_back({node->stamp, true_pose});
  }

  // 5. Factors.
  const Eigen::Matrix3d odometry_info2 = Information2(config.odometry);
  const Eigen::Matrix3d loop_info2 = Information2(config.loop_closures.noise);
  const Eigen::Matrix<double, 6, 6> odometry_info3 =
      Information3(config.odometry);
  const Eigen::Matrix<double, 6, 6> loop_info3 =
      Information3(config.loop_closures.noise);
  for (size_t e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    const bool odometry = edge.kind == Edge::kOdometry;
    Factor factor;
    bool made;
    if (truth.is_3d) {
      made = MakeBetweenSE3(Pose3Key(edge.i), Pose3Key(edge.j), z3[e],
                            odometry ? odometry_info3 : loop_info3, &factor,
                            error);
    } else {
      made = MakeBetweenSE2(Pose2Key(edge.i), Pose2Key(edge.j), z2[e],
                            odometry ? odometry_info2 : loop_info2, &factor,
                            error);
    }
    const FactorId id = made ? graph.AddFactor(std::move(factor)) : -1;
    if (id < 0) {
      if (made) *error = "internal error: a factor was rejected by the graph";
      return false;
    }
    if (odometry) {
      result->odometry_factors.push_back(id);
    } else {
      result->loop_closure_factors.push_back(id);
      if (edge.kind == Edge::kOutlier) result->outlier_factors.push_back(id);
    }
  }
  CountDimensions(result);
  return true;
}

void SetNodeValues(const std::map<Key, std::vector<double>>& values,
                   Graph* graph) {
  for (const auto& [key, value] : values) {
    Node* node = graph->FindNode(key);
    if (node == nullptr || node->value.size() != value.size()) continue;
    std::copy(value.begin(), value.end(), node->value.begin());
  }
}

}  // namespace slam
