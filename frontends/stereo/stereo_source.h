// A KITTI-style stereo sequence (datasets/kitti_sequence_io.h) as the frame
// source of the visual SLAM pipeline (frontends/visual/frame_source.h):
// each rectified pair decoded (stereo_images.h) and turned into ORB
// features with stereo matches (stereo_features.h), in a given playback
// order with given stamps.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_SOURCE_H_
#define SLAM_FRONTENDS_STEREO_STEREO_SOURCE_H_

#include <string>
#include <vector>

#include "datasets/kitti_sequence_io.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/visual/frame_source.h"

namespace slam {

class StereoSequenceSource : public VisualFrameSource {
 public:
  // Frame k is the sequence's pair order[k], stamped stamps[k] (one stamp
  // per entry of order); the sequence must outlive the source.
  StereoSequenceSource(const KittiSequence* sequence, std::vector<size_t> order,
                       std::vector<TimeNs> stamps,
                       const StereoFeatureConfig& features);

  // Decodes the first pair, which fixes the image size (checked against the
  // calibration); false with "FILE: problem". Call before anything else.
  bool Open(std::string* error);

  size_t NumFrames() const override { return order_.size(); }
  const StereoCalibration& calibration() const override {
    return sequence_->calibration;
  }
  int width() const override { return width_; }
  int height() const override { return height_; }
  bool Load(size_t k, VisualImages* images, std::string* error) const override;
  StereoFeatureFrame Extract(const VisualImages& images,
                             StereoFeatureTimings* timings) const override;

 private:
  const KittiSequence* sequence_;
  std::vector<size_t> order_;
  std::vector<TimeNs> stamps_;
  StereoFeatureExtractor extractor_;
  int width_ = 0, height_ = 0;
  // The pair decoded by Open, handed out by the first Load(0).
  mutable StereoImages first_;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_SOURCE_H_
