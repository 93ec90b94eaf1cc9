// Listing the images of a folder in natural order (`slam vocabulary`,
// `slam loops`, and any reader or frontend that takes a folder of images).
#ifndef SLAM_DATASETS_IMAGE_LIST_H_
#define SLAM_DATASETS_IMAGE_LIST_H_

#include <string>
#include <vector>

namespace slam {

// The image files (jpg, jpeg, png, bmp, pgm, ppm, tif, tiff, webp) directly in
// `dir`, in natural order: digit runs compare as numbers, so 2.jpg comes
// before 10.jpg (a loop ground truth indexes images in that order). Fails
// naming the folder when it is missing or holds no image.
bool ListImages(const std::string& dir, std::vector<std::string>* paths,
                std::string* error);

// "a2b" < "a10b": digit runs compare by value, the rest byte-wise.
bool NaturalLess(const std::string& a, const std::string& b);

}  // namespace slam

#endif  // SLAM_DATASETS_IMAGE_LIST_H_
