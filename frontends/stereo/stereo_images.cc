#include "frontends/stereo/stereo_images.h"

#include "datasets/text_util.h"
#include "frontends/image_io.h"

namespace slam {
namespace {

std::string Number(double v) {
  std::string out;
  text::AppendDouble(v, &out);
  return out;
}

}  // namespace

bool LoadStereoImages(const KittiSequence& sequence, size_t k,
                      int expected_width, int expected_height,
                      StereoImages* images, std::string* error, int min_side) {
  const std::string& left_path = sequence.left_images[k];
  const std::string& right_path = sequence.right_images[k];
  images->index = static_cast<int64_t>(k);
  images->stamp = sequence.stamps[k];
  if (!ReadGrayImage(left_path, min_side, &images->left, error) ||
      !ReadGrayImage(right_path, min_side, &images->right, error)) {
    return false;
  }
  const cv::Size size = images->left.size();
  if (images->right.size() != size) {
    *error = right_path + ": " + std::to_string(images->right.cols) + "x" +
             std::to_string(images->right.rows) + " but the left image " +
             left_path + " is " + std::to_string(size.width) + "x" +
             std::to_string(size.height);
    return false;
  }
  if (expected_width > 0 &&
      (size.width != expected_width || size.height != expected_height)) {
    *error = left_path + ": " + std::to_string(size.width) + "x" +
             std::to_string(size.height) + " but the first frame is " +
             std::to_string(expected_width) + "x" +
             std::to_string(expected_height);
    return false;
  }
  const StereoCalibration& c = sequence.calibration;
  // A field of view between about 0.6 and 169 degrees across the width.
  if (c.fx < 0.05 * size.width || c.fx > 100.0 * size.width) {
    *error = left_path + ": the image is " + std::to_string(size.width) +
             " pixels wide but the focal length fx = " + Number(c.fx) + " of " +
             sequence.calibration_path +
             " is outside [0.05, 100] times that: the calibration is not "
             "for these images";
    return false;
  }
  if (c.cx < 0.25 * size.width || c.cx > 0.75 * size.width ||
      c.cy < 0.25 * size.height || c.cy > 0.75 * size.height) {
    *error = left_path + ": the image is " + std::to_string(size.width) + "x" +
             std::to_string(size.height) + " but the principal point (" +
             std::to_string(c.cx) + ", " + std::to_string(c.cy) + ") of " +
             sequence.calibration_path +
             " is not in its middle half: the calibration is for another "
             "image size";
    return false;
  }
  return true;
}

}  // namespace slam
