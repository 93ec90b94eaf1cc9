// Camera models shared by the camera factors (stereo_projection.h,
// reprojection.h), the landmark initialization and the I/O code.
//
// Camera frame: x right, y down, z forward (optical axis). A camera pose node
// is T_world_camera (camera-to-world): p_world = R * p_camera + t, so a world
// point is brought into the camera frame by p_camera = R^T (p_world - t).
//
// Rectified stereo (left camera is the pose; the right camera sits at
// +baseline along the left camera's x axis), point p = (x, y, z) in the left
// camera frame:
//   uL = fx x / z + cx,  uR = fx (x - baseline) / z + cx,  v = fy y / z + cy.
// Pinhole with radial-tangential (OpenCV / Kalibr "radtan") distortion:
//   xn = x / z, yn = y / z, r2 = xn^2 + yn^2, radial = 1 + k1 r2 + k2 r2^2,
//   xd = xn radial + 2 p1 xn yn + p2 (r2 + 2 xn^2),
//   yd = yn radial + p1 (r2 + 2 yn^2) + 2 p2 xn yn,
//   u = fx xd + cx,  v = fy yd + cy.
// All-zero distortion coefficients give the plain pinhole model.
//
// The Project functions are templates so that Ceres Jets pass through; they
// return false for points with z <= kMinDepth (behind or on the camera).
#ifndef SLAM_FACTORS_CAMERA_MODELS_H_
#define SLAM_FACTORS_CAMERA_MODELS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace slam {

constexpr double kMinDepth = 1e-9;

struct StereoCalibration {
  double fx = 1.0;
  double fy = 1.0;
  double cx = 0.0;
  double cy = 0.0;
  double baseline = 1.0;  // Metres, right camera at +baseline along x.
  bool operator==(const StereoCalibration& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy &&
           baseline == o.baseline;
  }
};

struct PinholeCalibration {
  double fx = 1.0;
  double fy = 1.0;
  double cx = 0.0;
  double cy = 0.0;
  double k1 = 0.0;  // Radial.
  double k2 = 0.0;
  double p1 = 0.0;  // Tangential.
  double p2 = 0.0;
  bool operator==(const PinholeCalibration& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy && k1 == o.k1 &&
           k2 == o.k2 && p1 == o.p1 && p2 == o.p2;
  }
  bool HasDistortion() const {
    return k1 != 0.0 || k2 != 0.0 || p1 != 0.0 || p2 != 0.0;
  }
};

// World point -> camera frame, with the camera pose stored as a node
// (t, q xyzw), camera-to-world.
template <typename T>
Eigen::Matrix<T, 3, 1> WorldToCamera(const T* const camera,
                                     const T* const point) {
  Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(camera);
  Eigen::Map<const Eigen::Quaternion<T>> q(camera + 3);
  Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(point);
  return q.conjugate() * (p - t);
}

// Camera-frame point -> (uL, uR, v).
template <typename T>
bool ProjectStereo(const StereoCalibration& c, const Eigen::Matrix<T, 3, 1>& p,
                   Eigen::Matrix<T, 3, 1>* uv) {
  if (!(p.z() > T(kMinDepth))) return false;
  const T inv_z = T(1.0) / p.z();
  (*uv)[0] = T(c.fx) * p.x() * inv_z + T(c.cx);
  (*uv)[1] = T(c.fx) * (p.x() - T(c.baseline)) * inv_z + T(c.cx);
  (*uv)[2] = T(c.fy) * p.y() * inv_z + T(c.cy);
  return true;
}

// Normalized image coordinates -> distorted normalized coordinates.
template <typename T>
Eigen::Matrix<T, 2, 1> DistortRadTan(const PinholeCalibration& c,
                                     const Eigen::Matrix<T, 2, 1>& n) {
  const T xn = n.x();
  const T yn = n.y();
  const T r2 = xn * xn + yn * yn;
  const T radial = T(1.0) + T(c.k1) * r2 + T(c.k2) * r2 * r2;
  return Eigen::Matrix<T, 2, 1>(
      xn * radial + T(2.0 * c.p1) * xn * yn + T(c.p2) * (r2 + T(2.0) * xn * xn),
      yn * radial + T(c.p1) * (r2 + T(2.0) * yn * yn) +
          T(2.0 * c.p2) * xn * yn);
}

// Camera-frame point -> (u, v) pixel.
template <typename T>
bool ProjectPinhole(const PinholeCalibration& c,
                    const Eigen::Matrix<T, 3, 1>& p,
                    Eigen::Matrix<T, 2, 1>* uv) {
  if (!(p.z() > T(kMinDepth))) return false;
  const T inv_z = T(1.0) / p.z();
  const Eigen::Matrix<T, 2, 1> d =
      DistortRadTan(c, Eigen::Matrix<T, 2, 1>(p.x() * inv_z, p.y() * inv_z));
  (*uv)[0] = T(c.fx) * d.x() + T(c.cx);
  (*uv)[1] = T(c.fy) * d.y() + T(c.cy);
  return true;
}

// Pixel -> undistorted normalized coordinates (x/z, y/z), by fixed-point
// iteration of the distortion model (exact for zero distortion); false if
// the iteration does not settle (strong distortion far outside the image).
inline bool UnprojectPinhole(const PinholeCalibration& c,
                             const Eigen::Vector2d& uv, Eigen::Vector2d* n) {
  const Eigen::Vector2d d((uv.x() - c.cx) / c.fx, (uv.y() - c.cy) / c.fy);
  Eigen::Vector2d x = d;
  if (!c.HasDistortion()) {
    *n = x;
    return true;
  }
  for (int it = 0; it < 100; ++it) {
    const Eigen::Vector2d err = DistortRadTan(c, x) - d;
    if (err.norm() < 1e-14) break;
    x -= err;
  }
  *n = x;
  return (DistortRadTan(c, x) - d).norm() < 1e-9;
}

}  // namespace slam

#endif  // SLAM_FACTORS_CAMERA_MODELS_H_
