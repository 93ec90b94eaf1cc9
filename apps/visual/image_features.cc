#include "apps/visual/image_features.h"

#include <cstdio>

#include <opencv2/features2d.hpp>

#include "frontends/image_io.h"

namespace slam {

bool ExtractOrbFeatures(const std::vector<std::string>& paths, int orb_features,
                        std::vector<ImageFeatures>* features,
                        std::string* error) {
  cv::Ptr<cv::ORB> orb = cv::ORB::create(orb_features);
  const int min_side = OrbMinImageSide(orb->getNLevels(), orb->getScaleFactor(),
                                       orb->getEdgeThreshold());
  features->assign(paths.size(), ImageFeatures());
  for (size_t i = 0; i < paths.size(); ++i) {
    cv::Mat image;
    if (!ReadGrayImage(paths[i], min_side, &image, error)) return false;
    orb->detectAndCompute(image, cv::noArray(), (*features)[i].keypoints,
                          (*features)[i].descriptors);
    if ((i + 1) % 50 == 0 || i + 1 == paths.size()) {
      std::fprintf(stderr, "\rfeatures: %zu / %zu images", i + 1, paths.size());
      if (i + 1 == paths.size()) std::fprintf(stderr, "\n");
    }
  }
  return true;
}

std::vector<cv::Mat> DescriptorsOf(const std::vector<ImageFeatures>& features,
                                   size_t* count) {
  std::vector<cv::Mat> descriptors;
  *count = 0;
  for (const ImageFeatures& f : features) {
    descriptors.push_back(f.descriptors);
    *count += f.descriptors.rows;
  }
  return descriptors;
}

}  // namespace slam
