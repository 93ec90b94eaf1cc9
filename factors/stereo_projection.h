// Rectified stereo observation (uL, uR, v) of a 3D point from an SE(3)
// camera pose (GTSAM's GenericStereoFactor, g2o's EdgeStereoSE3ProjectXYZ).
//
// Frames (factors/camera_models.h): the camera pose node C = (t, q) is
// T_world_camera (camera-to-world) of the LEFT camera, camera frame x right,
// y down, z forward; the point l is in the world frame; p = R^T (l - t).
// Prediction: uL = fx px/pz + cx, uR = fx (px - b)/pz + cx, v = fy py/pz + cy.
// Error (residual order uL, uR, v; pixels): e = prediction - measurement.
// Residual: r = L^T e with Omega = L L^T (3x3 over (uL, uR, v)).
// Parameter blocks: C (7: t, q xyzw), l (3). Residuals: 3.
// Points at or behind the camera (pz <= kMinDepth) make the evaluation fail
// (Ceres then rejects the step).
#ifndef SLAM_FACTORS_STEREO_PROJECTION_H_
#define SLAM_FACTORS_STEREO_PROJECTION_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "factors/camera_models.h"

namespace slam {

class StereoProjectionFactor {
 public:
  StereoProjectionFactor(const StereoCalibration& calibration,
                         const Eigen::Vector3d& measurement,
                         const Eigen::Matrix3d& sqrt_information)
      : calibration_(calibration),
        measurement_(measurement),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const camera, const T* const point,
                  T* residual) const {
    Eigen::Matrix<T, 3, 1> uv;
    if (!ProjectStereo(calibration_, WorldToCamera(camera, point), &uv)) {
      return false;
    }
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (uv - measurement_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const StereoCalibration& calibration,
                                     const Eigen::Vector3d& measurement,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<StereoProjectionFactor, 3, 7, 3>(
        new StereoProjectionFactor(calibration, measurement, sqrt_information));
  }

 private:
  StereoCalibration calibration_;
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_STEREO_PROJECTION_H_
