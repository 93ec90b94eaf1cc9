// The raw data of the stereo frontend: a rectified stereo image pair, and the
// features extracted from it (what the tracking works on; the simulator and
// the tests build feature frames directly, without images).
//
// Pixel coordinates: OpenCV's, origin at the centre of the top-left pixel,
// u to the right, v down (the camera model of factors/camera_models.h).
#ifndef SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_
#define SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_

#include <cstdint>
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
// sub-pixel u coordinate of the same point in the right image (negative:
// no stereo match; the keypoint is then a monocular observation).
struct StereoFeatureFrame {
  int64_t index = 0;
  TimeNs stamp = 0;
  std::vector<cv::KeyPoint> keypoints;  // octave = pyramid level.
  cv::Mat descriptors;                  // keypoints.size() x 32, CV_8U.
  std::vector<double> u_right;          // One per keypoint; < 0: none.
  bool HasStereo(size_t i) const { return u_right[i] >= 0.0; }
  size_t size() const { return keypoints.size(); }
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_FRAME_H_
