#include "factors/landmark_factors.h"

#include <cmath>

#include "core/information.h"
#include "factors/range_bearing_2d.h"
#include "factors/relative_point2.h"
#include "factors/relative_point3.h"
#include "factors/reprojection.h"
#include "factors/stereo_projection.h"

namespace slam {
namespace {

bool CheckCommon(const Key& pose, NodeKind pose_kind, const Key& point,
                 NodeKind point_kind, const Eigen::VectorXd& measurement,
                 const Eigen::MatrixXd& information, Eigen::MatrixXd* sqrt_info,
                 std::string* error) {
  if (pose.kind != pose_kind || point.kind != point_kind) {
    *error = std::string("factor needs a ") + NodeKindName(pose_kind) +
             " and a " + NodeKindName(point_kind) + " node, got " +
             pose.ToString() + " and " + point.ToString();
    return false;
  }
  if (!measurement.allFinite()) {
    *error = "measurement is not finite";
    return false;
  }
  if (!information.allFinite() || !SqrtInformation(information, sqrt_info)) {
    *error = "information matrix is not symmetric positive definite";
    return false;
  }
  return true;
}

bool CheckCamera(double fx, double fy, double extra, bool extra_positive,
                 std::string* error) {
  if (!(fx > 0.0) || !(fy > 0.0) || !std::isfinite(fx) || !std::isfinite(fy)) {
    *error = "focal lengths must be positive";
    return false;
  }
  if (extra_positive && !(extra > 0.0 && std::isfinite(extra))) {
    *error = "stereo baseline must be positive";
    return false;
  }
  return true;
}

}  // namespace

bool MakeRangeBearing2(const Key& pose, const Key& point, double range,
                       double bearing, const Eigen::Matrix2d& information,
                       Factor* factor, std::string* error) {
  Eigen::MatrixXd sqrt_info;
  const Eigen::Vector2d z(range, bearing);
  if (!CheckCommon(pose, NodeKind::kPose2, point, NodeKind::kPoint2, z,
                   information, &sqrt_info, error)) {
    return false;
  }
  factor->type = FactorType::kRangeBearing2;
  factor->keys = {pose, point};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(RangeBearing2Factor::Create(range, bearing, sqrt_info));
  return true;
}

bool MakeRelativePoint2(const Key& pose, const Key& point,
                        const Eigen::Vector2d& measurement,
                        const Eigen::Matrix2d& information, Factor* factor,
                        std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!CheckCommon(pose, NodeKind::kPose2, point, NodeKind::kPoint2,
                   measurement, information, &sqrt_info, error)) {
    return false;
  }
  factor->type = FactorType::kRelativePoint2;
  factor->keys = {pose, point};
  factor->measurement = measurement;
  factor->information = information;
  factor->cost.reset(RelativePoint2Factor::Create(measurement, sqrt_info));
  return true;
}

bool MakeRelativePoint3(const Key& pose, const Key& point,
                        const Eigen::Vector3d& measurement, const Pose3& offset,
                        const Eigen::Matrix3d& information, Factor* factor,
                        std::string* error) {
  Eigen::MatrixXd sqrt_info;
  Eigen::VectorXd z(10);
  z << measurement, offset.t, offset.q.coeffs();
  if (!CheckCommon(pose, NodeKind::kPose3, point, NodeKind::kPoint3, z,
                   information, &sqrt_info, error)) {
    return false;
  }
  factor->type = FactorType::kRelativePoint3;
  factor->keys = {pose, point};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(
      RelativePoint3Factor::Create(measurement, offset, sqrt_info));
  return true;
}

bool MakeStereo(const Key& camera, const Key& point,
                const StereoCalibration& calibration,
                const Eigen::Vector3d& uL_uR_v,
                const Eigen::Matrix3d& information, Factor* factor,
                std::string* error) {
  Eigen::MatrixXd sqrt_info;
  Eigen::VectorXd z(8);
  z << uL_uR_v, calibration.fx, calibration.fy, calibration.cx, calibration.cy,
      calibration.baseline;
  if (!CheckCommon(camera, NodeKind::kPose3, point, NodeKind::kPoint3, z,
                   information, &sqrt_info, error) ||
      !CheckCamera(calibration.fx, calibration.fy, calibration.baseline, true,
                   error)) {
    return false;
  }
  factor->type = FactorType::kStereo;
  factor->keys = {camera, point};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(
      StereoProjectionFactor::Create(calibration, uL_uR_v, sqrt_info));
  return true;
}

bool MakeReprojection(const Key& camera, const Key& point,
                      const PinholeCalibration& calibration,
                      const Eigen::Vector2d& uv,
                      const Eigen::Matrix2d& information, Factor* factor,
                      std::string* error) {
  Eigen::MatrixXd sqrt_info;
  Eigen::VectorXd z(10);
  z << uv, calibration.fx, calibration.fy, calibration.cx, calibration.cy,
      calibration.k1, calibration.k2, calibration.p1, calibration.p2;
  if (!CheckCommon(camera, NodeKind::kPose3, point, NodeKind::kPoint3, z,
                   information, &sqrt_info, error) ||
      !CheckCamera(calibration.fx, calibration.fy, 0.0, false, error)) {
    return false;
  }
  factor->type = FactorType::kReprojection;
  factor->keys = {camera, point};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(ReprojectionFactor::Create(calibration, uv, sqrt_info));
  return true;
}

bool IsLandmarkFactor(FactorType type) {
  switch (type) {
    case FactorType::kRangeBearing2:
    case FactorType::kRelativePoint2:
    case FactorType::kRelativePoint3:
    case FactorType::kStereo:
    case FactorType::kReprojection:
      return true;
    default:
      return false;
  }
}

Pose3 SensorOffsetOf(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  Pose3 offset;  // Not Pose3(t, q): it would renormalize (bits may move).
  offset.t = m.segment<3>(3);
  offset.q = Eigen::Quaterniond(m[9], m[6], m[7], m[8]);
  return offset;
}

StereoCalibration StereoCalibrationOf(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  StereoCalibration c;
  c.fx = m[3];
  c.fy = m[4];
  c.cx = m[5];
  c.cy = m[6];
  c.baseline = m[7];
  return c;
}

PinholeCalibration PinholeCalibrationOf(const Factor& factor) {
  const Eigen::VectorXd& m = factor.measurement;
  PinholeCalibration c;
  c.fx = m[2];
  c.fy = m[3];
  c.cx = m[4];
  c.cy = m[5];
  c.k1 = m[6];
  c.k2 = m[7];
  c.p1 = m[8];
  c.p2 = m[9];
  return c;
}

bool RemakeLandmarkFactor(const Factor& in, Factor* out, std::string* error) {
  const Eigen::VectorXd& m = in.measurement;
  static const int kSizes[] = {2, 2, 10, 8, 10};
  if (!IsLandmarkFactor(in.type) || in.keys.size() != 2) {
    *error = "not a landmark factor";
    return false;
  }
  const int expected = kSizes[static_cast<int>(in.type) -
                              static_cast<int>(FactorType::kRangeBearing2)];
  const int dim =
      expected == 8 ? 3 : (in.type == FactorType::kRelativePoint3 ? 3 : 2);
  if (m.size() != expected || in.information.rows() != dim ||
      in.information.cols() != dim) {
    *error = "malformed landmark factor measurement or information";
    return false;
  }
  bool ok = false;
  switch (in.type) {
    case FactorType::kRangeBearing2:
      ok = MakeRangeBearing2(in.keys[0], in.keys[1], m[0], m[1], in.information,
                             out, error);
      break;
    case FactorType::kRelativePoint2:
      ok = MakeRelativePoint2(in.keys[0], in.keys[1], m.head<2>(),
                              in.information, out, error);
      break;
    case FactorType::kRelativePoint3:
      ok = MakeRelativePoint3(in.keys[0], in.keys[1], m.head<3>(),
                              SensorOffsetOf(in), in.information, out, error);
      break;
    case FactorType::kStereo:
      ok = MakeStereo(in.keys[0], in.keys[1], StereoCalibrationOf(in),
                      m.head<3>(), in.information, out, error);
      break;
    case FactorType::kReprojection:
      ok = MakeReprojection(in.keys[0], in.keys[1], PinholeCalibrationOf(in),
                            m.head<2>(), in.information, out, error);
      break;
    default:
      break;
  }
  if (ok) out->loss = in.loss;
  return ok;
}

PixelErrorStats CameraPixelErrors(const Graph& graph) {
  PixelErrorStats stats;
  double sum = 0.0;
  for (const auto& [id, f] : graph.factors()) {
    if (f.type != FactorType::kStereo && f.type != FactorType::kReprojection) {
      continue;
    }
    const double* camera = graph.FindNode(f.keys[0])->value.data();
    const double* point = graph.FindNode(f.keys[1])->value.data();
    const Eigen::Vector3d p = WorldToCamera(camera, point);
    ++stats.factors;
    if (f.type == FactorType::kStereo) {
      Eigen::Vector3d uv;
      if (!ProjectStereo(StereoCalibrationOf(f), p, &uv)) {
        ++stats.behind;
        continue;
      }
      sum += (uv - f.measurement.head<3>()).squaredNorm();
      stats.coordinates += 3;
    } else {
      Eigen::Vector2d uv;
      if (!ProjectPinhole(PinholeCalibrationOf(f), p, &uv)) {
        ++stats.behind;
        continue;
      }
      sum += (uv - f.measurement.head<2>()).squaredNorm();
      stats.coordinates += 2;
    }
  }
  if (stats.coordinates > 0) stats.rms = std::sqrt(sum / stats.coordinates);
  return stats;
}

}  // namespace slam
