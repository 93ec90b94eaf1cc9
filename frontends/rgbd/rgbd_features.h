// RGB-D keypoints as stereo-like measurements for the visual SLAM pipeline
// (frontends/visual/visual_slam.h), ORB-SLAM2's way: a keypoint with a
// valid depth z gets the u coordinate it would have in a virtual right
// camera `virtual_baseline` metres to the right,
//
//   u_R = u_L - fx * b / z,
//
// so that the rectified stereo factor (factors/stereo_projection.h), the
// tracking, the keyframes and the bundle adjustment of the stereo pipeline
// serve RGB-D unchanged. Its noise (pixel_sigma * 1.2^octave on u_R) is a
// depth noise sigma_z = z^2 / (fx b) * sigma_u, growing with the square of
// the depth as a structured-light sensor's does. A keypoint without depth
// (0: no measurement, or outside [min_depth, max_depth]) is a monocular
// observation.
//
// Per frame:
//  1. ORB keypoints and descriptors on the grey image, spread over the
//     image (StereoFeatureExtractor::DetectAndDescribe, the stereo
//     pipeline's detector and settings).
//  2. Undistortion: the keypoints move to the undistorted pinhole image
//     (cv::undistortPoints with the camera's k1 k2 p1 p2 k3); keypoints that
//     leave the image are dropped.
//  3. Depth: the registered depth image at the keypoint's (distorted, i.e.
//     measured) pixel, nearest pixel, unless its neighbourhood shows a depth
//     discontinuity (depth_radius, max_depth_step); the virtual right
//     coordinate from it.
#ifndef SLAM_FRONTENDS_RGBD_RGBD_FEATURES_H_
#define SLAM_FRONTENDS_RGBD_RGBD_FEATURES_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "factors/camera_models.h"
#include "frontends/rgbd/rgbd_camera.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_frame.h"

namespace slam {

struct RgbdConfig {
  double depth_factor = 5000.0;  // Depth image units per metre (TUM: 5000).
  // The depth noise the virtual right coordinate implies is
  // sigma_z = z^2 sigma_u / (fx b). The Kinect / Xtion structured-light
  // sensors of TUM RGB-D measure disparity in 1/8 pixel over a 7.5 cm
  // baseline at fx ~ 580: a depth step of 2.9 mm x z^2, which 0.5 px (the
  // keypoint sigma at the finest level) gives with b = 0.34 m. ORB-SLAM2's
  // TUM setting bf = 40 (b = 0.08 m) is a depth noise 4 times larger,
  // which lets the depth tell the pose less than it can.
  double virtual_baseline = 0.34;  // m.
  double min_depth = 0.3;          // m; closer readings are not used.
  // Farther keypoints are monocular. The sensor's specified range (Kinect 1:
  // 0.8-4 m); the noise model already weighs a far depth by z^-4
  // (sigma_z 4.5 cm at 4 m). Not ORB-SLAM2's ThDepth (40 baselines, 3.1 m):
  // ORB-SLAM2 keeps every depth reading as a measurement and uses ThDepth
  // only to choose which points a keyframe creates. A limit inside the room
  // starves the map when the camera faces its far end: a keypoint without
  // depth makes no map point (TUM fr1/rpy frames 43-52 look at a wall
  // 3.6-3.9 m away; with 3.2 m about half of their keypoints had no depth
  // and the inliers fell from 150-300 to 64-116).
  double max_depth = 4.0;  // m.
  // Depth discontinuities: a keypoint (a corner, often on an object's
  // outline) whose depth neighbourhood (+-depth_radius pixels) holds a
  // missing reading or depths differing by more than max_depth_step times
  // its depth has no reliable depth (foreground or background, or a mixed
  // pixel between them): it stays monocular. 0: no test.
  int depth_radius = 2;
  double max_depth_step = 0.03;
  // The colour camera captures on its own fixed-rate clock (Kinect 1 /
  // Xtion: 30 Hz) and the stamps are the driver's arrival times: poses are
  // estimated at the capture instants fitted to the stamps and written at
  // the stamps (frontends/visual/capture_clock.h). On TUM fr1/rpy the
  // stamps jitter by 2.3 ms rms around a 33.301 ms clock, and taking the
  // poses for those of the stamps cost 0.5 -> 0.38 deg of per-frame
  // rotation error (README).
  bool fixed_rate_capture = true;
};

bool ValidateRgbdConfig(const RgbdConfig& config, std::string* error);

// The camera of the undistorted keypoints with the virtual baseline.
StereoCalibration VirtualStereoCalibration(const RgbdCamera& camera,
                                           const RgbdConfig& config);

// u_R of a keypoint at u with depth z (z valid: in [min_depth, max_depth]),
// or StereoFeatureFrame::kNoRightCoordinate (no depth measurement); negative
// values are measurements (near points at the left edge of the image).
double VirtualRightU(double u, double depth,
                     const StereoCalibration& virtual_camera,
                     const RgbdConfig& config);

class RgbdFeatureExtractor {
 public:
  RgbdFeatureExtractor(const StereoFeatureConfig& features,
                       const RgbdCamera& camera, const RgbdConfig& config);

  // Steps 1-3 on a grey image and its depth (CV_32F metres, same size).
  StereoFeatureFrame Extract(const cv::Mat& grey, const cv::Mat& depth,
                             StereoFeatureTimings* timings) const;
  // Steps 2-3 for given keypoints (for tests): keypoints whose undistorted
  // position leaves the width x height image are dropped with their row.
  StereoFeatureFrame Measure(const std::vector<cv::KeyPoint>& keypoints,
                             const cv::Mat& descriptors,
                             const cv::Mat& depth) const;
  // Step 2 alone: undistorted pixel positions.
  std::vector<cv::Point2f> Undistort(
      const std::vector<cv::KeyPoint>& keypoints) const;

  const StereoCalibration& calibration() const { return calibration_; }
  // The smallest image side the ORB pyramid can take.
  int MinImageSide() const { return orb_.MinImageSide(); }

 private:
  // The depth at a pixel (0: none or a discontinuity, step 3).
  double DepthAt(const cv::Mat& depth, int col, int row) const;

  RgbdCamera camera_;
  RgbdConfig config_;
  StereoCalibration calibration_;
  StereoFeatureExtractor orb_;
  cv::Mat k_, distortion_;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_RGBD_RGBD_FEATURES_H_
