// Features of a rectified stereo pair: ORB keypoints spread over the image,
// and their correspondences along the rectified rows.
//
//  1. ORB (OpenCV) on each image: FAST corners on a scale pyramid
//     (scale_factor, levels), at most max_features, spread evenly: the image
//     is cut into cells of cell_size pixels and each cell keeps its
//     max_per_cell strongest corners (grid bucketing), so that texture-rich
//     areas do not take every feature; then the rotated BRIEF descriptors
//     of the kept corners only. The pyramid is built once (each level then
//     an ORB of one level, see DetectAndDescribe): the corners and
//     descriptors are those of OpenCV's multi-level ORB.
//     With grid_fast (off by default), each level's corners are instead
//     found per cell: FAST over the level, each cell's max_per_cell
//     strongest by FAST score at fast_threshold (at min_fast_threshold in a
//     cell that has none), ORB's Harris response of those only, the same
//     bucketing, and ORB's orientation and descriptor of the kept corners
//     only; every textured cell then has octave-0 corners (OpenCV's ORB
//     keeps a level's strongest corners over the whole image, so octave 0's
//     share sits where the contrast is highest).
//  2. Stereo correspondence for every left keypoint: the right keypoints
//     within row_tolerance * scale^octave rows, of a neighbouring octave,
//     at a disparity in [min_disparity, max_disparity]; the one with the
//     smallest Hamming distance is taken when that distance is at most
//     max_descriptor_distance and below ratio times the second smallest
//     (repeated texture along a row gives two close candidates: refused).
//     A right keypoint goes to the left keypoint that matches it best.
//  3. Sub-pixel refinement: the sum of absolute differences of a
//     (2 patch_radius + 1)^2 patch around the left keypoint against the
//     right image at integer shifts within +-search_radius of the matched
//     position; a parabola through the best shift and its neighbours gives
//     a first sub-pixel disparity (refused when the minimum is at the border
//     of the search or the parabola moves it by more than a pixel), and
//     Gauss-Newton on the squared differences of the zero-mean patches,
//     both interpolated by half the shift in opposite directions, refines
//     it. The parabola through SAD values alone pulls disparities towards
//     whole pixels (pixel locking: 0.1 px at quarter pixels on the rendered
//     wall of tests/stereo_features_test.cc), and on far points a
//     disparity bias is a depth (scale) bias.
//  4. Depth limit: a stereo match whose depth fx b / d exceeds
//     max_depth_baselines * b (disparity below fx / max_depth_baselines) is
//     dropped as a stereo observation; the keypoint stays as a monocular
//     one. Far points carry little translation information and their
//     depth error grows with the square of the depth.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_FEATURES_H_
#define SLAM_FRONTENDS_STEREO_STEREO_FEATURES_H_

#include <string>
#include <vector>

#include <opencv2/features2d.hpp>

#include "frontends/stereo/stereo_frame.h"

namespace slam {

struct StereoFeatureConfig {
  int max_features = 3000;    // Per image, after bucketing.
  double scale_factor = 1.2;  // ORB pyramid.
  int levels = 8;
  int fast_threshold = 12;  // FAST intensity threshold.
  int cell_size = 32;       // Pixels, grid bucketing.
  int max_per_cell = 10;
  // Detection per cell (DetectGrid) instead of OpenCV's ORB per level:
  // every level's FAST corners, the strongest max_per_cell of each cell at
  // every level (min_fast_threshold where a cell has none at
  // fast_threshold), Harris responses of those only, the same bucketing,
  // and the orientation and descriptor of the kept corners only.
  bool grid_fast = false;
  int min_fast_threshold = 5;  // FAST threshold in cells without corners.
  // Stereo matching.
  double row_tolerance = 2.0;  // Pixels at octave 0, times scale^octave.
  double min_disparity = 0.0;  // Pixels; > 0 by the refinement.
  double max_disparity_fraction = 0.5;  // Of the image width.
  int max_descriptor_distance = 60;     // Hamming, of 256 bits.
  double ratio = 0.9;                   // Best / second best distance.
  int patch_radius = 5;                 // SAD patch (11 x 11).
  int search_radius = 5;                // Integer shifts searched.
  double max_depth_baselines = 80.0;    // Depth limit in baselines.
};

// Checks ranges; false with a message naming the setting.
bool ValidateStereoFeatureConfig(const StereoFeatureConfig& config,
                                 std::string* error);

// Timings of one extraction, milliseconds.
struct StereoFeatureTimings {
  double features_ms = 0.0;  // ORB on both images.
  double matching_ms = 0.0;  // Stereo correspondence and refinement.
};

class StereoFeatureExtractor {
 public:
  StereoFeatureExtractor(const StereoFeatureConfig& config,
                         const StereoCalibration& calibration);

  // The features of one pair (grayscale, 8-bit, same size).
  StereoFeatureFrame Extract(const StereoImages& images,
                             StereoFeatureTimings* timings) const;

  // The steps separately (for tests).
  void DetectAndDescribe(const cv::Mat& image,
                         std::vector<cv::KeyPoint>* keypoints,
                         cv::Mat* descriptors) const;
  void MatchStereo(const cv::Mat& left, const cv::Mat& right,
                   const std::vector<cv::KeyPoint>& left_keypoints,
                   const cv::Mat& left_descriptors,
                   const std::vector<cv::KeyPoint>& right_keypoints,
                   const cv::Mat& right_descriptors,
                   std::vector<double>* u_right) const;

  const StereoFeatureConfig& config() const { return config_; }
  // The smallest image side the ORB pyramid can take (OrbMinImageSide of
  // frontends/image_io.h; 39 pixels with the defaults).
  int MinImageSide() const;

 private:
  StereoFeatureConfig config_;
  StereoCalibration calibration_;
  // One single-level ORB per pyramid level, asked for the corners OpenCV's
  // multi-level ORB would keep on that level (see DetectAndDescribe).
  // Candidate corners of every level (grid_fast): FAST, the strongest
  // max_per_cell per cell and level, their Harris responses; `all` in
  // image coordinates (octave = level), `at_level` their level positions.
  void DetectGrid(const std::vector<cv::Mat>& pyramid,
                  std::vector<cv::KeyPoint>* all,
                  std::vector<cv::Point2f>* at_level) const;

  std::vector<cv::Ptr<cv::Feature2D>> level_orbs_;
  std::vector<float> level_scales_;  // scale_factor^level, as ORB's float.
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_FEATURES_H_
