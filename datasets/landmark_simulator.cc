// Landmark and camera worlds of the simulator (landmarks2d, landmarks3d,
// stereo, monocular); the model is documented in datasets/simulator.h.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/graph.h"
#include "core/keys.h"
#include "core/lie.h"
#include "datasets/simulator.h"
#include "datasets/simulator_internal.h"
#include "factors/camera_models.h"
#include "factors/landmark_factors.h"
#include "factors/landmark_init.h"
#include "factors/pose_factors.h"

namespace slam {
namespace simulator_internal {
namespace {

enum class Sensor {
  kRangeBearing2,
  kRelativePoint2,
  kRelativePoint3,
  kStereo,
  kMonocular,
};

// One observation of landmark `landmark` (index into the true points) from
// pose `pose`, with its noisy measurement.
struct Observation {
  int pose = 0;
  int landmark = 0;
  Sensor sensor = Sensor::kRangeBearing2;
  Eigen::VectorXd z;
};

// stereo and monocular: cameras on a horizontal circle about the origin,
// looking at it; camera frame x right, y down (world -z), z forward.
void CameraCircle(const SimulationConfig::World& world, TruePoses* truth) {
  truth->is_3d = true;
  for (int k = 0; k < world.num_poses; ++k) {
    const double a = 2.0 * M_PI * k / world.num_poses;
    const Eigen::Vector3d center(world.radius * std::cos(a),
                                 world.radius * std::sin(a), 0.0);
    Eigen::Matrix3d rotation;
    rotation.col(2) = -center.normalized();             // Forward.
    rotation.col(1) = Eigen::Vector3d(0.0, 0.0, -1.0);  // Down.
    rotation.col(0) = rotation.col(1).cross(rotation.col(2));
    truth->poses3.emplace_back(center, Eigen::Quaterniond(rotation));
    truth->positions.push_back(center);
  }
}

// The true landmark positions (z = 0 in 2D).
std::vector<Eigen::Vector3d> ScatterLandmarks(const SimulationConfig& config,
                                              const TruePoses& truth,
                                              Random* random) {
  const SimulationConfig::Landmarks& lm = config.landmarks;
  std::vector<Eigen::Vector3d> points;
  const std::string& type = config.world.type;
  if (type == "stereo" || type == "monocular") {
    while (static_cast<int>(points.size()) < lm.num_landmarks) {
      // One draw per statement: the order in which a compiler evaluates
      // constructor arguments is unspecified (gcc goes right to left, clang
      // left to right), which gave other landmarks per compiler. z, y, x is
      // gcc's order, so the data of the Release build stays as it was.
      const double z = random->Uniform(-1.0, 1.0);
      const double y = random->Uniform(-1.0, 1.0);
      const double x = random->Uniform(-1.0, 1.0);
      const Eigen::Vector3d p(x, y, z);
      if (p.squaredNorm() <= 1.0) points.push_back(lm.field_radius * p);
    }
    return points;
  }
  Eigen::Vector3d lo = truth.positions.front();
  Eigen::Vector3d hi = lo;
  for (const Eigen::Vector3d& p : truth.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int dims = truth.is_3d ? 3 : 2;
  for (int j = 0; j < lm.num_landmarks; ++j) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int d = 0; d < dims; ++d) {
      p[d] = random->Uniform(lo[d] - lm.margin, hi[d] + lm.margin);
    }
    points.push_back(p);
  }
  return points;
}

Pose3 SensorOffset(const SimulationConfig::Landmarks& lm) {
  const std::vector<double>& o = lm.sensor_offset;
  return Pose3(Eigen::Vector3d(o[0], o[1], o[2]),
               Eigen::Quaterniond(o[6], o[3], o[4], o[5]));
}

StereoCalibration StereoOf(const SimulationConfig::Camera& c) {
  StereoCalibration s;
  s.fx = c.fx;
  s.fy = c.fy;
  s.cx = c.cx;
  s.cy = c.cy;
  s.baseline = c.baseline;
  return s;
}

PinholeCalibration PinholeOf(const SimulationConfig::Camera& c) {
  PinholeCalibration p;
  p.fx = c.fx;
  p.fy = c.fy;
  p.cx = c.cx;
  p.cy = c.cy;
  p.k1 = c.k1;
  p.k2 = c.k2;
  p.p1 = c.p1;
  p.p2 = c.p2;
  return p;
}

bool InImage(const SimulationConfig::Camera& c, double u, double v) {
  return u >= 0.0 && u < c.width && v >= 0.0 && v < c.height;
}

// The sensors of a world, in the order their factors are added per pose and
// landmark.
std::vector<Sensor> SensorsOf(const SimulationConfig& config) {
  const std::string& type = config.world.type;
  if (type == "landmarks3d") return {Sensor::kRelativePoint3};
  if (type == "stereo") return {Sensor::kStereo};
  if (type == "monocular") return {Sensor::kMonocular};
  const std::string& o = config.landmarks.observations;
  if (o == "range_bearing") return {Sensor::kRangeBearing2};
  if (o == "relative_position") return {Sensor::kRelativePoint2};
  return {Sensor::kRangeBearing2, Sensor::kRelativePoint2};
}

// The noise-free measurement of point p from pose k, if the sensor sees it.
bool TrueMeasurement(const SimulationConfig& config, const TruePoses& truth,
                     int k, const Eigen::Vector3d& p, Sensor sensor,
                     Eigen::VectorXd* z) {
  const SimulationConfig::Landmarks& lm = config.landmarks;
  const SimulationConfig::Camera& cam = config.camera;
  switch (sensor) {
    case Sensor::kRangeBearing2:
    case Sensor::kRelativePoint2: {
      const Pose2& x = truth.poses2[k];
      const Eigen::Vector2d local =
          RotationMatrix2D(x.theta).transpose() * (p.head<2>() - x.t);
      const double range = local.norm();
      const double bearing = std::atan2(local.y(), local.x());
      if (range > lm.max_range || range < 1e-6 ||
          std::abs(bearing) > 0.5 * lm.field_of_view) {
        return false;
      }
      if (sensor == Sensor::kRangeBearing2) {
        *z = Eigen::Vector2d(range, bearing);
      } else {
        *z = local;
      }
      return true;
    }
    case Sensor::kRelativePoint3: {
      const Eigen::Vector3d local =
          (truth.poses3[k] * SensorOffset(lm)).Inverse() * p;
      if (local.norm() > lm.max_range) return false;
      *z = local;
      return true;
    }
    case Sensor::kStereo:
    case Sensor::kMonocular: {
      const Eigen::Vector3d local = truth.poses3[k].Inverse() * p;
      if (local.z() < cam.min_depth || local.z() > cam.max_depth) return false;
      if (sensor == Sensor::kStereo) {
        Eigen::Vector3d uv;
        if (!ProjectStereo(StereoOf(cam), local, &uv) ||
            !InImage(cam, uv[0], uv[2]) || !InImage(cam, uv[1], uv[2])) {
          return false;
        }
        *z = uv;
      } else {
        Eigen::Vector2d uv;
        if (!ProjectPinhole(PinholeOf(cam), local, &uv) ||
            !InImage(cam, uv[0], uv[1])) {
          return false;
        }
        *z = uv;
      }
      return true;
    }
  }
  return false;
}

// Per-coordinate sigmas of a sensor's measurement.
Eigen::VectorXd Sigmas(const SimulationConfig::Landmarks& lm, Sensor sensor) {
  switch (sensor) {
    case Sensor::kRangeBearing2:
      return Eigen::Vector2d(lm.sigma_range, lm.sigma_bearing);
    case Sensor::kRelativePoint2:
      return Eigen::Vector2d::Constant(lm.sigma_position);
    case Sensor::kRelativePoint3:
      return Eigen::Vector3d::Constant(lm.sigma_position);
    case Sensor::kStereo:
      return Eigen::Vector3d::Constant(lm.sigma_pixel);
    case Sensor::kMonocular:
      return Eigen::Vector2d::Constant(lm.sigma_pixel);
  }
  return Eigen::VectorXd();
}

// Monocular: the largest angle between the first observation's ray and a
// later one (the pair the landmark initialization triangulates).
double Parallax(const TruePoses& truth, const Eigen::Vector3d& p,
                const std::vector<int>& poses) {
  const Eigen::Vector3d first = (p - truth.poses3[poses[0]].t).normalized();
  double best = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector3d ray = (p - truth.poses3[poses[i]].t).normalized();
    best = std::max(best, std::atan2(first.cross(ray).norm(), first.dot(ray)));
  }
  return best;
}

bool MakeObservationFactor(const SimulationConfig& config, const Key& pose,
                           const Key& point, const Observation& o,
                           Factor* factor, std::string* error) {
  const Eigen::VectorXd sigmas = Sigmas(config.landmarks, o.sensor);
  const Eigen::VectorXd info = sigmas.array().square().inverse();
  switch (o.sensor) {
    case Sensor::kRangeBearing2:
      return MakeRangeBearing2(pose, point, o.z[0], o.z[1],
                               Eigen::Matrix2d(info.asDiagonal()), factor,
                               error);
    case Sensor::kRelativePoint2:
      return MakeRelativePoint2(
          pose, point, o.z, Eigen::Matrix2d(info.asDiagonal()), factor, error);
    case Sensor::kRelativePoint3:
      return MakeRelativePoint3(
          pose, point, o.z, SensorOffset(config.landmarks),
          Eigen::Matrix3d(info.asDiagonal()), factor, error);
    case Sensor::kStereo:
      return MakeStereo(pose, point, StereoOf(config.camera), o.z,
                        Eigen::Matrix3d(info.asDiagonal()), factor, error);
    case Sensor::kMonocular:
      return MakeReprojection(pose, point, PinholeOf(config.camera), o.z,
                              Eigen::Matrix2d(info.asDiagonal()), factor,
                              error);
  }
  return false;
}

bool AllFinite(const Graph& graph, const std::vector<const Factor*>& factors) {
  for (const Factor* f : factors) {
    double chi2 = 0.0;
    if (!graph.FactorChi2(*f, &chi2) || !std::isfinite(chi2)) return false;
  }
  return true;
}

// The landmark initialization (factors/landmark_init.h) of point `key` from
// the observations `subset` only: on a graph holding just their poses and the
// point. False if it finds no proper position (a monocular point needs two
// rays).
bool InitializeFromSubset(const Graph& graph, const Key& key,
                          const std::vector<const Factor*>& subset,
                          std::vector<double>* value) {
  Graph part;
  for (const Factor* f : subset) {
    const Node* pose = graph.FindNode(f->keys[0]);
    if (!part.HasNode(pose->key)) part.AddNode(pose->key, pose->value);
  }
  part.AddNode(key, *value);
  for (const Factor* f : subset) {
    if (part.AddFactor(*f) < 0) return false;
  }
  const LandmarkInitReport report = InitializeLandmarks(&part);
  if (report.initialized != 1 || report.weak > 0) return false;
  *value = part.FindNode(key)->value;
  return true;
}

// The observation subsets tried, in order, to place a point again:
// monocular, the pairs in time order whose true rays are min_parallax apart
// (cameras close in time: little drift between them); stereo, single
// observations by decreasing disparity (the most precise depth first);
// otherwise single observations in time order.
std::vector<std::vector<size_t>> Subsets(
    const SimulationConfig& config, const TruePoses& truth,
    const Eigen::Vector3d& point, const std::vector<Observation>& observations,
    const std::vector<size_t>& indices) {
  std::vector<std::vector<size_t>> subsets;
  const std::string& type = config.world.type;
  if (type == "monocular") {
    const double min_angle = std::max(config.landmarks.min_parallax, 1e-6);
    for (size_t a = 0; a < indices.size(); ++a) {
      for (size_t b = a + 1; b < indices.size(); ++b) {
        if (Parallax(truth, point,
                     {observations[indices[a]].pose,
                      observations[indices[b]].pose}) >= min_angle) {
          subsets.push_back({indices[a], indices[b]});
        }
      }
    }
    return subsets;
  }
  for (size_t i : indices) subsets.push_back({i});
  if (type == "stereo") {
    const auto disparity = [&](const std::vector<size_t>& s) {
      const Eigen::VectorXd& z = observations[s[0]].z;
      return z[0] - z[1];
    };
    std::stable_sort(
        subsets.begin(), subsets.end(),
        [&](const std::vector<size_t>& a, const std::vector<size_t>& b) {
          return disparity(a) > disparity(b);
        });
  }
  return subsets;
}

// The landmark initialization places a point from its first observation(s)
// through the drifting dead-reckoned poses. Monocular points are all placed
// from the earliest working pair of rays instead of its first-and-widest
// pair: those two cameras are far apart in time (first and last of the
// circle), their dead-reckoned poses have drifted apart, and the point can
// land anywhere, even behind a camera (initial reprojection RMS 141308 px
// against 22 px on configs/simulate_monocular.yaml). Other points are placed
// again only when an observation is undefined at their value (a stereo point
// from a small noisy disparity behind the cameras across the circle), from
// the subsets above, until every factor of the point is defined.
// `observations` and `factors` are parallel. Counts the points whose first
// value left an observation undefined in *undefined; false if one stays so.
bool PlacePoints(const SimulationConfig& config, const TruePoses& truth,
                 const std::vector<Eigen::Vector3d>& points,
                 const std::vector<Observation>& observations,
                 const std::vector<FactorId>& factors, Graph* graph,
                 int* undefined, std::string* error) {
  *undefined = 0;
  const bool monocular = config.world.type == "monocular";
  std::map<Key, std::vector<size_t>> by_point;  // Indices of observations.
  for (size_t i = 0; i < factors.size(); ++i) {
    by_point[graph->FindFactor(factors[i])->keys[1]].push_back(i);
  }
  for (const auto& [key, indices] : by_point) {
    std::vector<const Factor*> obs;
    for (size_t i : indices) obs.push_back(graph->FindFactor(factors[i]));
    const bool defined = AllFinite(*graph, obs);
    if (defined && !monocular) continue;
    std::vector<double>& value = graph->FindNode(key)->value;
    const std::vector<double> first = value;
    const Eigen::Vector3d& point = points[observations[indices[0]].landmark];
    bool placed = false;
    for (const std::vector<size_t>& subset :
         Subsets(config, truth, point, observations, indices)) {
      std::vector<const Factor*> part;
      for (size_t i : subset) part.push_back(graph->FindFactor(factors[i]));
      std::vector<double> candidate = value;
      if (!InitializeFromSubset(*graph, key, part, &candidate)) continue;
      std::copy(candidate.begin(), candidate.end(), value.begin());
      placed = AllFinite(*graph, obs);
      if (placed) break;
    }
    if (!defined) ++*undefined;
    if (placed) continue;
    if (defined) {  // Keep the first value.
      std::copy(first.begin(), first.end(), value.begin());
      continue;
    }
    *error = "internal error: no initial value of " + key.ToString() +
             " makes all its observations defined";
    return false;
  }
  return true;
}

bool CheckNonNegative(double value, const char* name, std::string* error) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    *error = std::string(name) + " must be >= 0";
    return false;
  }
  return true;
}

bool CheckFinite(double value, const char* name, std::string* error) {
  if (!std::isfinite(value)) {
    *error = std::string(name) + " must be a finite number";
    return false;
  }
  return true;
}

}  // namespace

bool IsLandmarkWorld(const std::string& type) {
  return type == "landmarks2d" || type == "landmarks3d" || type == "stereo" ||
         type == "monocular";
}

bool ValidateLandmarkConfig(const SimulationConfig& config,
                            std::string* error) {
  const SimulationConfig::Landmarks& lm = config.landmarks;
  const SimulationConfig::Camera& c = config.camera;
  if (lm.num_landmarks < 1 || lm.num_landmarks > 10000000) {
    *error = "landmarks.num_landmarks must be in [1, 10000000]";
    return false;
  }
  if (lm.min_observations < 1) {
    *error = "landmarks.min_observations must be at least 1";
    return false;
  }
  if (lm.observations != "range_bearing" &&
      lm.observations != "relative_position" && lm.observations != "both") {
    *error = "landmarks.observations '" + lm.observations +
             "' is not one of range_bearing, relative_position, both";
    return false;
  }
  if (!CheckNonNegative(lm.margin, "landmarks.margin", error) ||
      !CheckPositive(lm.field_radius, "landmarks.field_radius", error) ||
      !CheckPositive(lm.max_range, "landmarks.max_range", error) ||
      !CheckPositive(lm.field_of_view, "landmarks.field_of_view", error) ||
      !CheckPositive(lm.sigma_range, "landmarks.sigma_range", error) ||
      !CheckPositive(lm.sigma_bearing, "landmarks.sigma_bearing", error) ||
      !CheckPositive(lm.sigma_position, "landmarks.sigma_position", error) ||
      !CheckPositive(lm.sigma_pixel, "landmarks.sigma_pixel", error) ||
      !CheckNonNegative(lm.min_parallax, "landmarks.min_parallax", error)) {
    return false;
  }
  if (lm.field_of_view > 2.0 * M_PI) {
    *error = "landmarks.field_of_view must be at most 2 pi";
    return false;
  }
  if (lm.sigma_bearing > 1.0) {
    *error = "landmarks.sigma_bearing must be at most 1 rad";
    return false;
  }
  if (lm.sensor_offset.size() != 7) {
    *error = "landmarks.sensor_offset must have 7 numbers: x y z qx qy qz qw";
    return false;
  }
  double q_norm_sq = 0.0;
  for (size_t i = 0; i < 7; ++i) {
    if (!CheckFinite(lm.sensor_offset[i], "landmarks.sensor_offset", error)) {
      return false;
    }
    if (i >= 3) q_norm_sq += lm.sensor_offset[i] * lm.sensor_offset[i];
  }
  if (std::abs(q_norm_sq - 1.0) > 1e-6) {
    *error =
        "landmarks.sensor_offset quaternion (qx qy qz qw) must have "
        "unit length";
    return false;
  }
  if (!CheckPositive(c.fx, "camera.fx", error) ||
      !CheckPositive(c.fy, "camera.fy", error) ||
      !CheckFinite(c.cx, "camera.cx", error) ||
      !CheckFinite(c.cy, "camera.cy", error) ||
      !CheckPositive(c.baseline, "camera.baseline", error) ||
      !CheckFinite(c.k1, "camera.k1", error) ||
      !CheckFinite(c.k2, "camera.k2", error) ||
      !CheckFinite(c.p1, "camera.p1", error) ||
      !CheckFinite(c.p2, "camera.p2", error) ||
      !CheckPositive(c.min_depth, "camera.min_depth", error)) {
    return false;
  }
  if (c.width < 1 || c.height < 1) {
    *error = "camera.width and camera.height must be positive";
    return false;
  }
  if (!(c.max_depth > c.min_depth) || !std::isfinite(c.max_depth)) {
    *error = "camera.max_depth must be larger than camera.min_depth";
    return false;
  }
  if (config.world.type == "monocular" && !lm.odometry &&
      config.world.num_poses < 3) {
    *error =
        "world.num_poses must be at least 3 for a monocular world "
        "without odometry (two poses are fixed)";
    return false;
  }
  return true;
}

bool SimulateLandmarkWorld(const SimulationConfig& config, Random* random,
                           SimulationResult* result, std::string* error) {
  const SimulationConfig::Landmarks& lm = config.landmarks;
  const std::string& type = config.world.type;

  // 1. The true trajectory and landmarks.
  TruePoses truth;
  if (type == "landmarks2d") {
    GridWorld2d(config.world, random, &truth);
  } else if (type == "landmarks3d") {
    GridWorld3d(config.world, random, &truth);
  } else {
    CameraCircle(config.world, &truth);
  }
  const int n = truth.size();
  result->is_3d = truth.is_3d;
  const std::vector<Eigen::Vector3d> points =
      ScatterLandmarks(config, truth, random);

  // 2. Which landmark each pose sees (pose order, then landmark order), and
  // which landmarks are kept.
  const std::vector<Sensor> sensors = SensorsOf(config);
  std::vector<Observation> observations;
  std::vector<std::vector<int>> seen_from(points.size());
  for (int k = 0; k < n; ++k) {
    for (size_t j = 0; j < points.size(); ++j) {
      bool seen = false;
      for (Sensor sensor : sensors) {
        Observation o;
        if (!TrueMeasurement(config, truth, k, points[j], sensor, &o.z)) {
          continue;
        }
        o.pose = k;
        o.landmark = static_cast<int>(j);
        o.sensor = sensor;
        observations.push_back(std::move(o));
        seen = true;
      }
      if (seen) seen_from[j].push_back(k);
    }
  }
  std::vector<int> landmark_id(points.size(), -1);
  int num_kept = 0;
  for (size_t j = 0; j < points.size(); ++j) {
    const int count = static_cast<int>(seen_from[j].size());
    if (count == 0 || count < lm.min_observations) continue;
    if (type == "monocular" &&
        (count < 2 || Parallax(truth, points[j], seen_from[j]) <
                          std::max(lm.min_parallax, 1e-6))) {
      continue;
    }
    landmark_id[j] = n + num_kept++;
  }
  observations.erase(std::remove_if(observations.begin(), observations.end(),
                                    [&](const Observation& o) {
                                      return landmark_id[o.landmark] < 0;
                                    }),
                     observations.end());

  // 3. Noise: the odometry, then the observations in factor order.
  std::vector<Pose2> z2(truth.is_3d ? 0 : n - 1);
  std::vector<Pose3> z3(truth.is_3d ? n - 1 : 0);
  for (int k = 0; k + 1 < n; ++k) {
    if (truth.is_3d) {
      z3[k] = truth.poses3[k].Inverse() * truth.poses3[k + 1] *
              SampleNoise3(config.odometry, random);
    } else {
      z2[k] = truth.poses2[k].Inverse() * truth.poses2[k + 1] *
              SampleNoise2(config.odometry, random);
    }
  }
  for (Observation& o : observations) {
    const Eigen::VectorXd sigmas = Sigmas(lm, o.sensor);
    for (int i = 0; i < o.z.size(); ++i) o.z[i] += sigmas[i] * random->Normal();
    if (o.sensor == Sensor::kRangeBearing2) o.z[1] = NormalizeAngle(o.z[1]);
  }

  // 4. Nodes: poses by dead reckoning from the fixed ones; points zero until
  // initialized from their observations (step 6).
  const bool fix_second = type == "monocular" && !lm.odometry;
  const auto is_fixed = [&](int k) { return k == 0 || (fix_second && k == 1); };
  Graph& graph = result->graph;
  std::vector<Pose2> dr2(truth.is_3d ? 0 : n);
  std::vector<Pose3> dr3(truth.is_3d ? n : 0);
  for (int k = 0; k < n; ++k) {
    if (truth.is_3d) {
      dr3[k] = is_fixed(k) ? truth.poses3[k] : dr3[k - 1] * z3[k - 1];
    } else {
      dr2[k] = is_fixed(k) ? truth.poses2[k] : dr2[k - 1] * z2[k - 1];
    }
  }
  for (int k = 0; k < n; ++k) {
    const Key key = truth.is_3d ? Pose3Key(k) : Pose2Key(k);
    Node* node = graph.AddNode(
        key, truth.is_3d ? Pose3Value(dr3[k]) : Pose2Value(dr2[k]));
    node->stamp = static_cast<TimeNs>(k) * kNanosecondsPerSecond;
    node->has_stamp = true;
    node->fixed = is_fixed(k);
    result->ground_truth[key] =
        truth.is_3d ? Pose3Value(truth.poses3[k]) : Pose2Value(truth.poses2[k]);
    result->ground_truth_trajectory.push_back(
        {node->stamp,
         truth.is_3d ? truth.poses3[k] : LiftPose2(truth.poses2[k])});
  }
  for (size_t j = 0; j < points.size(); ++j) {
    if (landmark_id[j] < 0) continue;
    const Key key =
        truth.is_3d ? Point3Key(landmark_id[j]) : Point2Key(landmark_id[j]);
    std::vector<double> value(points[j].data(),
                              points[j].data() + (truth.is_3d ? 3 : 2));
    graph.AddNode(key, std::vector<double>(value.size(), 0.0));
    result->ground_truth[key] = value;
    result->landmarks.push_back(key);
  }

  // 5. Factors: odometry, then the observations.
  const auto add = [&](Factor factor, std::vector<FactorId>* ids) {
    const FactorId id = graph.AddFactor(std::move(factor));
    if (id < 0) {
      *error = "internal error: a factor was rejected by the graph";
      return false;
    }
    ids->push_back(id);
    return true;
  };
  if (lm.odometry) {
    const Eigen::Matrix3d info2 = Information2(config.odometry);
    const Eigen::Matrix<double, 6, 6> info3 = Information3(config.odometry);
    for (int k = 0; k + 1 < n; ++k) {
      Factor factor;
      const bool made = truth.is_3d
                            ? MakeBetweenSE3(Pose3Key(k), Pose3Key(k + 1),
                                             z3[k], info3, &factor, error)
                            : MakeBetweenSE2(Pose2Key(k), Pose2Key(k + 1),
                                             z2[k], info2, &factor, error);
      if (!made || !add(std::move(factor), &result->odometry_factors)) {
        return false;
      }
    }
  }
  for (const Observation& o : observations) {
    const int id = landmark_id[o.landmark];
    const Key pose = truth.is_3d ? Pose3Key(o.pose) : Pose2Key(o.pose);
    const Key point = truth.is_3d ? Point3Key(id) : Point2Key(id);
    Factor factor;
    if (!MakeObservationFactor(config, pose, point, o, &factor, error) ||
        !add(std::move(factor), &result->landmark_factors)) {
      return false;
    }
  }

  // 6. Landmark initial values from their observations through the
  // dead-reckoned poses.
  const LandmarkInitReport init = InitializeLandmarks(&graph);
  if (init.failed > 0) {
    *error = "internal error: " + std::to_string(init.failed) +
             " landmarks could not be initialized";
    return false;
  }
  return PlacePoints(config, truth, points, observations,
                     result->landmark_factors, &graph,
                     &result->reinitialized_landmarks, error);
}

}  // namespace simulator_internal
}  // namespace slam
