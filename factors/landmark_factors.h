// Builders that turn a landmark or camera measurement and its information
// matrix into a graph Factor ready for Graph::AddFactor. The autodiff cost
// functions of these factors are instantiated in landmark_factors.cc only.
//
// Factor::measurement layouts (what the writers and the landmark
// initialization read back; the calibration and the sensor offset travel
// with each factor so that a graph is self-contained):
//   kRangeBearing2  keys {Pose2, Point2}: (range, bearing).
//   kRelativePoint2 keys {Pose2, Point2}: (x, y) in the robot frame.
//   kRelativePoint3 keys {Pose3, Point3}: (x, y, z) in the sensor frame,
//                   then the sensor offset (tx, ty, tz, qx, qy, qz, qw): 10.
//   kStereo         keys {Pose3, Point3}: (uL, uR, v, fx, fy, cx, cy, b): 8.
//   kReprojection   keys {Pose3, Point3}: (u, v, fx, fy, cx, cy, k1, k2, p1,
//                   p2): 10.
// Factor::information is over the error in the factor's documented residual
// order (see the factor's header).
#ifndef SLAM_FACTORS_LANDMARK_FACTORS_H_
#define SLAM_FACTORS_LANDMARK_FACTORS_H_

#include <Eigen/Core>
#include <string>

#include "core/graph.h"
#include "core/keys.h"
#include "core/lie.h"
#include "factors/camera_models.h"

namespace slam {

// Each builder fails (returns false, sets *error) when the information matrix
// is not symmetric positive definite, a key has the wrong kind, or the
// measurement / calibration is not finite (or, for cameras, a focal length or
// the baseline is not positive).
bool MakeRangeBearing2(const Key& pose, const Key& point, double range,
                       double bearing, const Eigen::Matrix2d& information,
                       Factor* factor, std::string* error);
bool MakeRelativePoint2(const Key& pose, const Key& point,
                        const Eigen::Vector2d& measurement,
                        const Eigen::Matrix2d& information, Factor* factor,
                        std::string* error);
bool MakeRelativePoint3(const Key& pose, const Key& point,
                        const Eigen::Vector3d& measurement, const Pose3& offset,
                        const Eigen::Matrix3d& information, Factor* factor,
                        std::string* error);
bool MakeStereo(const Key& camera, const Key& point,
                const StereoCalibration& calibration,
                const Eigen::Vector3d& uL_uR_v,
                const Eigen::Matrix3d& information, Factor* factor,
                std::string* error);
bool MakeReprojection(const Key& camera, const Key& point,
                      const PinholeCalibration& calibration,
                      const Eigen::Vector2d& uv,
                      const Eigen::Matrix2d& information, Factor* factor,
                      std::string* error);

// Rebuilds a factor of one of the five kinds above from its type, keys,
// measurement and information (e.g. after copying between graphs).
bool RemakeLandmarkFactor(const Factor& in, Factor* out, std::string* error);

// True for the five factor types above.
bool IsLandmarkFactor(FactorType type);

// Parts of a factor's measurement (layouts above; the factor must be of the
// matching type).
Pose3 SensorOffsetOf(const Factor& factor);  // kRelativePoint3.
StereoCalibration StereoCalibrationOf(const Factor& factor);  // kStereo.
PinholeCalibration PinholeCalibrationOf(
    const Factor& factor);  // kReprojection.

// Raw (not whitened) pixel errors of the camera factors (kStereo: uL, uR, v;
// kReprojection: u, v) at the graph's current values.
struct PixelErrorStats {
  int factors = 0;      // Camera factors evaluated.
  int coordinates = 0;  // Pixel coordinates summed over.
  int behind = 0;       // Factors whose point is behind the camera (left out).
  double rms = 0.0;     // sqrt(sum e^2 / coordinates), pixels.
};
PixelErrorStats CameraPixelErrors(const Graph& graph);

}  // namespace slam

#endif  // SLAM_FACTORS_LANDMARK_FACTORS_H_
