// Decoding the images of a stereo sequence (datasets/kitti_sequence_io.h)
// into 8-bit grayscale pairs, with the checks that catch a wrong folder or
// calibration before any work is done.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_IMAGES_H_
#define SLAM_FRONTENDS_STEREO_STEREO_IMAGES_H_

#include <string>

#include "datasets/kitti_sequence_io.h"
#include "frontends/stereo/stereo_frame.h"

namespace slam {

// Frame k of the sequence: both images read with cv::IMREAD_GRAYSCALE
// (colour images are converted; lossless WebP decodes exactly) through
// ReadGrayImage (frontends/image_io.h: regular files only, the header's size
// checked before decoding, no OpenCV exception escapes; sides below
// `min_side` refused). Errors name the file: unreadable or empty image, left
// and right sizes that differ, a size that differs from frame 0's
// (expected_width/height > 0), or a size that does not fit the calibration (the
// principal point must lie in the middle half of the image: full-resolution
// images with a half-resolution calib.txt, or the reverse, fail here; fx must
// be 0.05 to 100 times the width, a field of view of 169 to 0.6 degrees).
bool LoadStereoImages(const KittiSequence& sequence, size_t k,
                      int expected_width, int expected_height,
                      StereoImages* images, std::string* error,
                      int min_side = 1);

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_IMAGES_H_
