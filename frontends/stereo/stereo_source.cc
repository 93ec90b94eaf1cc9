#include "frontends/stereo/stereo_source.h"

#include <utility>

#include "frontends/stereo/stereo_images.h"

namespace slam {

StereoSequenceSource::StereoSequenceSource(const KittiSequence* sequence,
                                           std::vector<size_t> order,
                                           std::vector<TimeNs> stamps,
                                           const StereoFeatureConfig& features)
    : sequence_(sequence),
      order_(std::move(order)),
      stamps_(std::move(stamps)),
      extractor_(features, sequence->calibration) {}

bool StereoSequenceSource::Open(std::string* error) {
  if (order_.empty()) {
    *error = sequence_->dir + ": no frames to process";
    return false;
  }
  if (!LoadStereoImages(*sequence_, order_[0], 0, 0, &first_, error,
                        extractor_.MinImageSide())) {
    return false;
  }
  width_ = first_.left.cols;
  height_ = first_.left.rows;
  return true;
}

bool StereoSequenceSource::Load(size_t k, VisualImages* images,
                                std::string* error) const {
  StereoImages pair;
  if (k == 0 && !first_.left.empty()) {
    pair = std::move(first_);
    first_ = StereoImages();
  } else if (!LoadStereoImages(*sequence_, order_[k], width_, height_, &pair,
                               error, extractor_.MinImageSide())) {
    return false;
  }
  images->index = static_cast<int64_t>(k);
  images->stamp = stamps_[k];
  images->left = std::move(pair.left);
  images->right = std::move(pair.right);
  images->depth.release();
  return true;
}

StereoFeatureFrame StereoSequenceSource::Extract(
    const VisualImages& images, StereoFeatureTimings* timings) const {
  StereoImages pair;
  pair.index = images.index;
  pair.stamp = images.stamp;
  pair.left = images.left;
  pair.right = images.right;
  return extractor_.Extract(pair, timings);
}

}  // namespace slam
