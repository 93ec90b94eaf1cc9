// Monocular reprojection (u, v) of a 3D point from an SE(3) camera pose,
// pinhole model with optional radial-tangential distortion (k1 k2 p1 p2;
// all zero: plain pinhole). Model in factors/camera_models.h.
//
// Frames: the camera pose node C = (t, q) is T_world_camera
// (camera-to-world), camera frame x right, y down, z forward; the point l is
// in the world frame; p = R^T (l - t) is projected.
// Error (residual order u, v; pixels): e = project(p) - (u, v)_measured.
// Residual: r = L^T e with Omega = L L^T (2x2 over (u, v)).
// Parameter blocks: C (7: t, q xyzw), l (3). Residuals: 2.
// Points at or behind the camera (pz <= kMinDepth) make the evaluation fail
// (Ceres then rejects the step).
#ifndef SLAM_FACTORS_REPROJECTION_H_
#define SLAM_FACTORS_REPROJECTION_H_

#include <Eigen/Core>

#include "ceres/autodiff_cost_function.h"
#include "factors/camera_models.h"

namespace slam {

class ReprojectionFactor {
 public:
  ReprojectionFactor(const PinholeCalibration& calibration,
                     const Eigen::Vector2d& measurement,
                     const Eigen::Matrix2d& sqrt_information)
      : calibration_(calibration),
        measurement_(measurement),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const camera, const T* const point,
                  T* residual) const {
    Eigen::Matrix<T, 2, 1> uv;
    if (!ProjectPinhole(calibration_, WorldToCamera(camera, point), &uv)) {
      return false;
    }
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (uv - measurement_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const PinholeCalibration& calibration,
                                     const Eigen::Vector2d& measurement,
                                     const Eigen::Matrix2d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<ReprojectionFactor, 2, 7, 3>(
        new ReprojectionFactor(calibration, measurement, sqrt_information));
  }

 private:
  PinholeCalibration calibration_;
  Eigen::Vector2d measurement_;
  Eigen::Matrix2d sqrt_information_;
};

}  // namespace slam

#endif  // SLAM_FACTORS_REPROJECTION_H_
