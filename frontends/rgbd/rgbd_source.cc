#include "frontends/rgbd/rgbd_source.h"

#include <algorithm>
#include <utility>

#include <opencv2/imgcodecs.hpp>

#include "frontends/image_io.h"

namespace slam {
namespace {

std::string Where(const std::string& list, const TumImageEntry& e) {
  return list + ":" + std::to_string(e.line) + ": " + e.path + ": ";
}

std::string SizeText(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

}  // namespace

RgbdSequenceSource::RgbdSequenceSource(const TumRgbdSequence* sequence,
                                       size_t frames, const RgbdCamera& camera,
                                       const RgbdConfig& config,
                                       const StereoFeatureConfig& features)
    : sequence_(sequence),
      frames_(frames == 0 ? sequence->frames.size()
                          : std::min(frames, sequence->frames.size())),
      camera_(camera),
      config_(config),
      extractor_(features, camera, config) {}

bool RgbdSequenceSource::Open(std::string* error) {
  if (frames_ == 0) {
    *error = sequence_->dir + ": no frames to process";
    return false;
  }
  if (!Load(0, &first_, error)) return false;
  width_ = first_.left.cols;
  height_ = first_.left.rows;
  const TumRgbdFrame& f = sequence_->frames[0];
  if (camera_.cx < 0.25 * width_ || camera_.cx > 0.75 * width_ ||
      camera_.cy < 0.25 * height_ || camera_.cy > 0.75 * height_) {
    *error = Where(sequence_->rgb_list, f.rgb) + "the image is " +
             SizeText(first_.left) + " but the principal point (" +
             std::to_string(camera_.cx) + ", " + std::to_string(camera_.cy) +
             ") of camera " + camera_.name +
             " is not in its middle half: the camera is for another image "
             "size";
    return false;
  }
  return true;
}

bool RgbdSequenceSource::Load(size_t k, VisualImages* images,
                              std::string* error) const {
  if (k == 0 && !first_.left.empty()) {
    *images = std::move(first_);
    first_ = VisualImages();
    return true;
  }
  const TumRgbdFrame& f = sequence_->frames[k];
  images->index = static_cast<int64_t>(k);
  images->stamp = f.rgb.stamp;
  images->right.release();
  std::string image_error;
  if (!ReadGrayImage(f.rgb.path, extractor_.MinImageSide(), &images->left,
                     &image_error)) {
    *error = Where(sequence_->rgb_list, f.rgb) +
             "cannot read the colour image: " + image_error;
    return false;
  }
  if (width_ > 0 &&
      (images->left.cols != width_ || images->left.rows != height_)) {
    *error = Where(sequence_->rgb_list, f.rgb) + SizeText(images->left) +
             " but the first frame is " + std::to_string(width_) + "x" +
             std::to_string(height_);
    return false;
  }
  cv::Mat raw;
  const std::string where = Where(sequence_->depth_list, f.depth);
  if (!ReadImageChecked(f.depth.path, cv::IMREAD_UNCHANGED, 1, &raw,
                        &image_error)) {
    *error = where + "cannot read the depth image: " + image_error;
    return false;
  }
  if (raw.type() != CV_16UC1) {
    *error = where + "the depth image is " +
             (raw.depth() == CV_8U
                  ? std::string("8-bit")
                  : "of OpenCV type " + std::to_string(raw.type())) +
             " with " + std::to_string(raw.channels()) +
             " channel(s); TUM depth images are 16-bit single-channel PNG "
             "(depth_factor units per metre)";
    return false;
  }
  if (raw.size() != images->left.size()) {
    *error = where + "the depth image is " + SizeText(raw) +
             " but its colour image " + f.rgb.path + " is " +
             SizeText(images->left);
    return false;
  }
  raw.convertTo(images->depth, CV_32F, 1.0 / config_.depth_factor);
  return true;
}

StereoFeatureFrame RgbdSequenceSource::Extract(
    const VisualImages& images, StereoFeatureTimings* timings) const {
  StereoFeatureFrame frame =
      extractor_.Extract(images.left, images.depth, timings);
  frame.index = images.index;
  frame.stamp = images.stamp;
  return frame;
}

}  // namespace slam
