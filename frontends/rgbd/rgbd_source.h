// A TUM RGB-D recording (datasets/tum_rgbd_io.h) as the frame source of the
// visual SLAM pipeline (frontends/visual/frame_source.h): each associated
// colour / depth pair decoded and checked, then turned into keypoints with
// depth (rgbd_features.h). Frames are the associated pairs in colour order,
// stamped with the colour image's stamp.
//
// Decoding errors name the list file and line of the image: a colour image
// that cannot be read, a depth image that cannot be read, is not 16-bit
// single-channel, or differs in size from the colour image; a size other
// than frame 0's; a principal point outside the middle half of the image (a
// camera for another resolution).
#ifndef SLAM_FRONTENDS_RGBD_RGBD_SOURCE_H_
#define SLAM_FRONTENDS_RGBD_RGBD_SOURCE_H_

#include <string>

#include "datasets/tum_rgbd_io.h"
#include "frontends/rgbd/rgbd_features.h"
#include "frontends/visual/frame_source.h"

namespace slam {

class RgbdSequenceSource : public VisualFrameSource {
 public:
  // The first `frames` associated pairs (0: all) of the sequence, which must
  // outlive the source.
  RgbdSequenceSource(const TumRgbdSequence* sequence, size_t frames,
                     const RgbdCamera& camera, const RgbdConfig& config,
                     const StereoFeatureConfig& features);

  // Decodes the first frame, which fixes the image size; false with
  // "LIST:LINE: PATH: problem". Call before anything else.
  bool Open(std::string* error);

  size_t NumFrames() const override { return frames_; }
  const StereoCalibration& calibration() const override {
    return extractor_.calibration();
  }
  int width() const override { return width_; }
  int height() const override { return height_; }
  bool Load(size_t k, VisualImages* images, std::string* error) const override;
  StereoFeatureFrame Extract(const VisualImages& images,
                             StereoFeatureTimings* timings) const override;
  bool FixedRateCapture() const override { return config_.fixed_rate_capture; }

 private:
  const TumRgbdSequence* sequence_;
  size_t frames_;
  RgbdCamera camera_;
  RgbdConfig config_;
  RgbdFeatureExtractor extractor_;
  int width_ = 0, height_ = 0;
  mutable VisualImages first_;  // Decoded by Open, handed out by Load(0).
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_RGBD_RGBD_SOURCE_H_
