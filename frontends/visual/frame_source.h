// Where the visual SLAM pipeline (visual_slam.h) gets its frames: a source
// decodes frame k's images and turns them into features, keypoints with
// descriptors and, where the sensor measures depth, a right-image u
// coordinate (StereoFeatureFrame, frontends/stereo/stereo_frame.h). A
// rectified stereo pair gives it by stereo matching
// (frontends/stereo/stereo_source.h); an RGB-D frame by a virtual right
// camera from the registered depth (frontends/rgbd/rgbd_source.h). Tracking,
// keyframes, bundle adjustment and loop closing only see the features.
#ifndef SLAM_FRONTENDS_VISUAL_FRAME_SOURCE_H_
#define SLAM_FRONTENDS_VISUAL_FRAME_SOURCE_H_

#include <cstddef>
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "core/conventions.h"
#include "factors/camera_models.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_frame.h"

namespace slam {

// One frame's decoded images: a rectified stereo pair (left, right; 8-bit
// grey), or a colour image as 8-bit grey (left) with its registered depth
// (depth: CV_32F metres, 0 = no measurement).
struct VisualImages {
  int64_t index = 0;  // Frame number, in processing order.
  TimeNs stamp = 0;
  cv::Mat left;
  cv::Mat right;
  cv::Mat depth;
};

class VisualFrameSource {
 public:
  virtual ~VisualFrameSource() = default;

  virtual size_t NumFrames() const = 0;
  // The camera of the features: intrinsics of the (undistorted) keypoints
  // and the baseline of their right-image coordinate.
  virtual const StereoCalibration& calibration() const = 0;
  virtual int width() const = 0;
  virtual int height() const = 0;

  // Decodes frame k (k < NumFrames()), setting its index k and stamp. The
  // pipeline calls it for frame k + 1 on a worker thread while it extracts
  // and tracks frame k: it must not change what Extract reads. False with
  // "FILE: problem".
  virtual bool Load(size_t k, VisualImages* images,
                    std::string* error) const = 0;
  // The features of a decoded frame, with the milliseconds of detection
  // (features_ms) and of the right-coordinate step (matching_ms).
  virtual StereoFeatureFrame Extract(const VisualImages& images,
                                     StereoFeatureTimings* timings) const = 0;
  // True when the camera captures on a fixed-rate clock of its own and the
  // stamps are arrival times (RGB-D: Kinect 1 / Xtion): the pipeline then
  // takes each frame's pose as that of its capture instant and writes the
  // trajectory at the stamps (capture_clock.h). A stereo pair's stamps are
  // its capture times.
  virtual bool FixedRateCapture() const { return false; }
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_VISUAL_FRAME_SOURCE_H_
