// Image folders and ORB features for the place-recognition commands
// (`slam vocabulary`, `slam loops`).
#ifndef SLAM_APPS_VISUAL_IMAGE_FEATURES_H_
#define SLAM_APPS_VISUAL_IMAGE_FEATURES_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace slam {

// The image files (jpg, jpeg, png, bmp, pgm, ppm, tif, tiff, webp) directly in
// `dir`, in natural order: digit runs compare as numbers, so 2.jpg comes
// before 10.jpg (a loop ground truth indexes images in that order). Fails
// naming the folder when it is missing or holds no image.
bool ListImages(const std::string& dir, std::vector<std::string>* paths,
                std::string* error);

// "a2b" < "a10b": digit runs compare by value, the rest byte-wise.
bool NaturalLess(const std::string& a, const std::string& b);

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
