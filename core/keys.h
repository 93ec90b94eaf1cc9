// Typed node keys. A key is a node kind plus an integer id; two nodes of
// different kinds may share an id (as in GTSAM's symbols), while the g2o and
// TORO readers keep their files' single id space by giving every vertex the
// id written in the file.
#ifndef SLAM_CORE_KEYS_H_
#define SLAM_CORE_KEYS_H_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace slam {

enum class NodeKind : uint8_t {
  kPose2 = 0,    // SE(2): x, y, theta.
  kPose3,        // SE(3): tx, ty, tz, qx, qy, qz, qw.
  kPoint2,       // 2D landmark: x, y.
  kPoint3,       // 3D landmark: x, y, z.
  kVelocity3,    // Linear velocity in the world frame: vx, vy, vz.
  kImuBias,      // Gyroscope then accelerometer bias: bg(3), ba(3).
  kCalibration,  // Free-form calibration vector (size set per node).
};

// Number of doubles stored for a node kind (kCalibration: 0, variable).
int AmbientSize(NodeKind kind);
// Number of degrees of freedom of a node kind (kCalibration: 0, variable).
int TangentSize(NodeKind kind);
// Short lower-case name, e.g. "pose2".
const char* NodeKindName(NodeKind kind);

struct Key {
  NodeKind kind = NodeKind::kPose2;
  int64_t id = 0;

  Key() = default;
  Key(NodeKind k, int64_t i) : kind(k), id(i) {}

  bool operator==(const Key& o) const { return kind == o.kind && id == o.id; }
  bool operator!=(const Key& o) const { return !(*this == o); }
  bool operator<(const Key& o) const {
    return kind != o.kind ? kind < o.kind : id < o.id;
  }
  std::string ToString() const;
};

inline Key Pose2Key(int64_t id) { return Key(NodeKind::kPose2, id); }
inline Key Pose3Key(int64_t id) { return Key(NodeKind::kPose3, id); }
inline Key Point2Key(int64_t id) { return Key(NodeKind::kPoint2, id); }
inline Key Point3Key(int64_t id) { return Key(NodeKind::kPoint3, id); }
inline Key VelocityKey(int64_t id) { return Key(NodeKind::kVelocity3, id); }
inline Key ImuBiasKey(int64_t id) { return Key(NodeKind::kImuBias, id); }

struct KeyHash {
  size_t operator()(const Key& k) const {
    return std::hash<int64_t>()(k.id) ^
           (static_cast<size_t>(k.kind) * 0x9E3779B97F4A7C15ull);
  }
};

}  // namespace slam

#endif  // SLAM_CORE_KEYS_H_
