#include "core/keys.h"

namespace slam {

int AmbientSize(NodeKind kind) {
  switch (kind) {
    case NodeKind::kPose2:
      return 3;
    case NodeKind::kPose3:
      return 7;
    case NodeKind::kPoint2:
      return 2;
    case NodeKind::kPoint3:
      return 3;
    case NodeKind::kVelocity3:
      return 3;
    case NodeKind::kImuBias:
      return 6;
    case NodeKind::kCalibration:
      return 0;
  }
  return 0;
}

int TangentSize(NodeKind kind) {
  return kind == NodeKind::kPose3 ? 6 : AmbientSize(kind);
}

const char* NodeKindName(NodeKind kind) {
  switch (kind) {
    case NodeKind::kPose2:
      return "pose2";
    case NodeKind::kPose3:
      return "pose3";
    case NodeKind::kPoint2:
      return "point2";
    case NodeKind::kPoint3:
      return "point3";
    case NodeKind::kVelocity3:
      return "velocity3";
    case NodeKind::kImuBias:
      return "imu_bias";
    case NodeKind::kCalibration:
      return "calibration";
  }
  return "unknown";
}

std::string Key::ToString() const {
  return std::string(NodeKindName(kind)) + "(" + std::to_string(id) + ")";
}

}  // namespace slam
