// The raw data of the stereo frontend: a rectified stereo image pair, and the
// features extracted from it (what the tracking works on; the simulator and
// the tests build feature frames directly, without images).
//
// Pixel coordinates: OpenCV's, origin at the centre of the top-left pixel,
// u to the right, v down (the camera model of factors/camera_models.h).
#ifndef SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_
#define SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>

#include "core/conventions.h"
#include "factors/camera_models.h"

namespace slam {

// A rectified pair, 8-bit grayscale, same size.
struct StereoImages {
  int64_t index = 0;
  TimeNs stamp = 0;
  cv::Mat left;
  cv::Mat right;
};

// Features of one stereo frame: left keypoints with their ORB descriptors
// (one 32-byte row each) and, where the stereo matching found one, the
// sub-pixel u coordinate of the same point in the right image
// (kNoRightCoordinate: no stereo match; the keypoint is then a monocular
// observation). The coordinate may be negative: an RGB-D keypoint's virtual
// right coordinate u - fx b / z lies left of the image for near points at
// its left edge (b = 0.34 m: the left quarter of the image at 1.5 m), and
// its depth is still a measurement.
struct StereoFeatureFrame {
  static constexpr double kNoRightCoordinate =
      std::numeric_limits<double>::quiet_NaN();
  int64_t index = 0;
  TimeNs stamp = 0;
  std::vector<cv::KeyPoint> keypoints;  // octave = pyramid level.
  cv::Mat descriptors;                  // keypoints.size() x 32, CV_8U.
  std::vector<double> u_right;          // One per keypoint; NaN: none.
  bool HasStereo(size_t i) const { return !std::isnan(u_right[i]); }
  size_t size() const { return keypoints.size(); }
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_
