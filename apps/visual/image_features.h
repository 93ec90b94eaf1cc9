// ORB features of image folders for the place-recognition commands
// (`slam vocabulary`, `slam loops`); the folders are listed by
// datasets/image_list.h.
#ifndef SLAM_APPS_VISUAL_IMAGE_FEATURES_H_
#define SLAM_APPS_VISUAL_IMAGE_FEATURES_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "datasets/image_list.h"

namespace slam {

struct ImageFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  // CV_8U, 32-byte ORB rows.
};

// Reads every image as grey and extracts up to `orb_features` ORB features;
// progress on stderr. Fails naming the first unreadable image.
bool ExtractOrbFeatures(const std::vector<std::string>& paths, int orb_features,
                        std::vector<ImageFeatures>* features,
                        std::string* error);

// The descriptor matrices of the images; *count receives their total rows.
std::vector<cv::Mat> DescriptorsOf(const std::vector<ImageFeatures>& features,
                                   size_t* count);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_IMAGE_FEATURES_H_
