#include "factors/landmark_init.h"

#include <map>
#include <vector>

#include "core/triangulation.h"
#include "factors/camera_models.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

// Ray of a monocular observation in the world frame.
bool ObservationRay(const Graph& graph, const Factor& f,
                    Eigen::Vector3d* origin, Eigen::Vector3d* direction) {
  const Pose3 camera = NodePose3(*graph.FindNode(f.keys[0]));
  Eigen::Vector2d n;
  if (!UnprojectPinhole(PinholeCalibrationOf(f), f.measurement.head<2>(), &n)) {
    return false;
  }
  *origin = camera.t;
  *direction = camera.q * Eigen::Vector3d(n.x(), n.y(), 1.0);
  return true;
}

// Sets *value from the observations of one point; false if none could.
bool PlacePoint(const Graph& graph, const std::vector<const Factor*>& obs,
                std::vector<double>* value, bool* weak) {
  *weak = false;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays;
  for (const Factor* f : obs) {
    const Node& pose = *graph.FindNode(f->keys[0]);
    const Eigen::VectorXd& m = f->measurement;
    switch (f->type) {
      case FactorType::kRangeBearing2: {
        const Eigen::Vector2d p =
            InvertRangeBearing(NodePose2(pose), m[0], m[1]);
        *value = {p.x(), p.y()};
        return true;
      }
      case FactorType::kRelativePoint2: {
        const Pose2 x = NodePose2(pose);
        const Eigen::Vector2d p = x.t + RotationMatrix2D(x.theta) * m.head<2>();
        *value = {p.x(), p.y()};
        return true;
      }
      case FactorType::kRelativePoint3: {
        const Eigen::Vector3d p = (NodePose3(pose) * SensorOffsetOf(*f)) *
                                  Eigen::Vector3d(m.head<3>());
        *value = {p.x(), p.y(), p.z()};
        return true;
      }
      case FactorType::kStereo: {
        const StereoCalibration c = StereoCalibrationOf(*f);
        Eigen::Vector3d p;
        if (TriangulateStereo(NodePose3(pose), c.fx, c.fy, c.cx, c.cy,
                              c.baseline, m.head<3>(), &p)) {
          *value = {p.x(), p.y(), p.z()};
          return true;
        }
        break;
      }
      case FactorType::kReprojection: {
        Eigen::Vector3d o, d;
        if (ObservationRay(graph, *f, &o, &d)) rays.emplace_back(o, d);
        break;
      }
      default:
        break;
    }
  }
  if (rays.empty()) return false;
  const auto& [o1, d1] = rays.front();
  double best_cos = 1.0;
  Eigen::Vector3d best;
  bool found = false;
  for (size_t k = 1; k < rays.size(); ++k) {
    const auto& [o2, d2] = rays[k];
    const double c = d1.normalized().dot(d2.normalized());
    Eigen::Vector3d p;
    if (c < best_cos && TriangulateMidpoint(o1, d1, o2, d2, &p)) {
      best_cos = c;
      best = p;
      found = true;
    }
  }
  if (!found) {
    best = o1 + d1.normalized();
    *weak = true;
  }
  *value = {best.x(), best.y(), best.z()};
  return true;
}

}  // namespace

LandmarkInitReport InitializeLandmarks(Graph* graph,
                                       const std::set<Key>* only) {
  LandmarkInitReport report;
  std::map<Key, std::vector<const Factor*>> observations;
  for (const auto& [id, f] : graph->factors()) {
    if (!IsLandmarkFactor(f.type) || f.keys.size() != 2) continue;
    const Key& point = f.keys[1];
    if (only != nullptr && only->count(point) == 0) continue;
    observations[point].push_back(&f);
  }
  std::vector<double> value;
  for (const auto& [key, obs] : observations) {
    Node* node = graph->FindNode(key);
    bool weak = false;
    if (node == nullptr || !PlacePoint(*graph, obs, &value, &weak) ||
        value.size() != node->value.size()) {
      ++report.failed;
      continue;
    }
    std::copy(value.begin(), value.end(), node->value.begin());
    ++report.initialized;
    if (weak) ++report.weak;
  }
  return report;
}

}  // namespace slam
