// The stereo feature extractor on rendered images with known motion: a
// textured fronto-parallel wall rendered at ten times the resolution and
// averaged over 10 x 10 blocks (a camera integrating over its pixels), seen
// shifted by a known number of pixels (sub-pixel in the stereo pair, whole
// pixels between two views of the left camera).
#include "frontends/stereo/stereo_features.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace slam {
namespace {

constexpr int kUpsample = 10;

// A wall of blobs and edges (corners for FAST) at ten times the resolution.
cv::Mat RenderWorld(int width, int height, uint32_t seed) {
  cv::setRNGSeed(static_cast<int>(seed));
  cv::Mat world(height * kUpsample, width * kUpsample, CV_32F, cv::Scalar(0));
  // Blobs of several sizes, so that every pyramid level finds corners.
  for (int cell : {4, 8, 16}) {
    cv::Mat coarse(height / cell + 2, width / cell + 2, CV_32F);
    cv::randu(coarse, 0, 255);
    cv::Mat layer;
    cv::resize(coarse, layer,
               cv::Size(coarse.cols * cell * kUpsample,
                        coarse.rows * cell * kUpsample),
               0, 0, cv::INTER_NEAREST);
    world += layer(cv::Rect(0, 0, world.cols, world.rows)) / 3.0;
  }
  cv::GaussianBlur(world, world, cv::Size(0, 0), 0.6 * kUpsample);
  world.convertTo(world, CV_8U);
  return world;
}

// The image of the world seen from `shift` pixels (left) along x, with
// Gaussian noise of `noise` grey levels.
cv::Mat View(const cv::Mat& world, double shift, int width, int height,
             double noise, std::mt19937* rng) {
  const int x0 = static_cast<int>(std::lround(shift * kUpsample));
  cv::Mat crop = world(cv::Rect(x0, 0, width * kUpsample, height * kUpsample));
  cv::Mat out;
  cv::resize(crop, out, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  std::normal_distribution<double> gauss(0.0, noise);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      out.at<uchar>(y, x) = cv::saturate_cast<uchar>(
          out.at<uchar>(y, x) + (noise > 0 ? gauss(*rng) : 0.0));
    }
  }
  return out;
}

struct DisparityErrors {
  int matches = 0;
  double rms = 0.0;
  double max_abs_bias = 0.0;  // Largest mean error over the fractions.
  // Per octave of the left keypoint: the matches, and the largest mean error
  // over the fractions with at least 10 matches of that octave.
  std::vector<int> octave_matches;
  std::vector<double> octave_max_abs_bias;
};

DisparityErrors MeasureDisparity(const StereoFeatureConfig& config,
                                 double noise) {
  std::mt19937 rng(11);
  const int width = 320, height = 120;
  const StereoCalibration calibration{300.0, 300.0, 160.0, 60.0, 0.5};
  const StereoFeatureExtractor extractor(config, calibration);
  const cv::Mat world = RenderWorld(width + 40, height, 3);
  DisparityErrors out;
  out.octave_matches.assign(config.levels, 0);
  out.octave_max_abs_bias.assign(config.levels, 0.0);
  double sum2 = 0.0;
  for (int tenth = 0; tenth < 10; ++tenth) {
    const double d = 12.0 + 0.1 * tenth;
    StereoImages images;
    images.left = View(world, 0.0, width, height, noise, &rng);
    images.right = View(world, d, width, height, noise, &rng);
    const StereoFeatureFrame f = extractor.Extract(images, nullptr);
    double sum = 0.0;
    int n = 0;
    std::vector<double> octave_sum(config.levels, 0.0);
    std::vector<int> octave_n(config.levels, 0);
    for (size_t i = 0; i < f.size(); ++i) {
      if (!f.HasStereo(i)) continue;
      const double e = f.keypoints[i].pt.x - f.u_right[i] - d;
      if (std::abs(e) > 2.0) continue;  // A wrong match: not sub-pixel.
      sum += e;
      sum2 += e * e;
      ++n;
      octave_sum[f.keypoints[i].octave] += e;
      ++octave_n[f.keypoints[i].octave];
    }
    out.matches += n;
    if (n > 0) out.max_abs_bias = std::max(out.max_abs_bias, std::abs(sum / n));
    for (int l = 0; l < config.levels; ++l) {
      out.octave_matches[l] += octave_n[l];
      if (octave_n[l] >= 10) {
        out.octave_max_abs_bias[l] = std::max(
            out.octave_max_abs_bias[l], std::abs(octave_sum[l] / octave_n[l]));
      }
    }
  }
  out.rms = std::sqrt(sum2 / std::max(1, out.matches));
  return out;
}

TEST(StereoFeaturesTest, SubPixelDisparityOfARenderedWall) {
  // Known fractional disparities d = 12.0, 12.1, ..., 12.9: the mean error
  // at each must stay below 0.05 px (no pull towards whole pixels, pixel
  // locking, which a parabola through SAD values has: 0.1 px here; a
  // disparity bias is a depth bias on far points).
  for (double noise : {0.0, 2.0}) {
    const DisparityErrors e = MeasureDisparity(StereoFeatureConfig(), noise);
    std::printf(
        "image noise %.0f: %d stereo matches, rms %.3f px, largest "
        "mean error at one sub-pixel disparity %.3f px\n",
        noise, e.matches, e.rms, e.max_abs_bias);
    EXPECT_GT(e.matches, 1000);
    EXPECT_LT(e.rms, 0.25);
    EXPECT_LT(e.max_abs_bias, 0.05);
  }
}

TEST(StereoFeaturesTest, SubPixelDisparityIsUnbiasedAtEveryOctave) {
  // The same wall, per octave of the left keypoint: a corner found on a
  // coarse pyramid level is matched at its full-resolution position, and
  // the refinement runs on full-resolution patches at every octave, so the
  // disparity of every octave must be as unbiased as octave 0's (a bias
  // that grew with the octave would scale depths more at full resolution,
  // which keeps more corners of the higher octaves).
  const StereoFeatureConfig config;
  const DisparityErrors e = MeasureDisparity(config, 2.0);
  int octaves = 0;
  for (int l = 0; l < config.levels; ++l) {
    std::printf(
        "octave %d: %d stereo matches, largest mean error at one sub-pixel "
        "disparity %.3f px\n",
        l, e.octave_matches[l], e.octave_max_abs_bias[l]);
    if (e.octave_matches[l] < 150) continue;  // Too few for a mean.
    ++octaves;
    EXPECT_LT(e.octave_max_abs_bias[l], 0.05) << "octave " << l;
  }
  EXPECT_GE(octaves, 4);
}

// Mean error of the keypoint positions per octave when the image moves
// down by exactly a whole number of pixels: the same corners, found in both
// views, must move with it. Several shifts, so that the rounding of the
// shifts to each level's pixels averages out.
struct ShiftErrors {
  std::vector<double> mean;
  std::vector<int> corners;
};

ShiftErrors MeanShiftErrorPerOctave(const StereoFeatureConfig& config) {
  const int width = 613, height = 185;  // The KITTI half-resolution size.
  const StereoCalibration calibration{350.0, 350.0, 300.0, 90.0, 0.5};
  const StereoFeatureExtractor extractor(config, calibration);
  const int max_shift = 100;
  // The world turned by 90 degrees: a vertical shift of the view.
  const cv::Mat world = RenderWorld(height + max_shift + 4, width, 5).t();
  auto view = [&](int shift) {
    cv::Mat out;
    cv::resize(world(cv::Rect(0, shift * kUpsample, width * kUpsample,
                              height * kUpsample)),
               out, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    return out;
  };
  std::vector<cv::KeyPoint> ka;
  cv::Mat da;
  extractor.DetectAndDescribe(view(0), &ka, &da);
  ShiftErrors out;
  out.mean.assign(config.levels, 0.0);
  out.corners.assign(config.levels, 0);
  for (int shift = 40; shift <= max_shift; shift += 3) {
    std::vector<cv::KeyPoint> kb;
    cv::Mat db;
    extractor.DetectAndDescribe(view(shift), &kb, &db);
    for (size_t i = 0; i < ka.size(); ++i) {
      const int level = ka[i].octave;
      const double s = std::pow(config.scale_factor, level);
      int best = -1;
      double best_d = 1.5 * s;
      for (size_t j = 0; j < kb.size(); ++j) {
        if (kb[j].octave != level) continue;
        const double d = std::hypot(kb[j].pt.x - ka[i].pt.x,
                                    kb[j].pt.y + shift - ka[i].pt.y);
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(j);
        }
      }
      if (best < 0) continue;
      out.mean[level] += kb[best].pt.y + shift - ka[i].pt.y;
      ++out.corners[level];
    }
  }
  for (int l = 0; l < config.levels; ++l) {
    if (out.corners[l] > 0) out.mean[l] /= out.corners[l];
    std::printf("octave %d: %d corners, mean error of the shift %.3f px\n", l,
                out.corners[l], out.mean[l]);
  }
  return out;
}

TEST(StereoFeaturesTest, KeypointsOfEveryOctaveMoveWithTheImage) {
  // Without the rounded level sizes (positions scaled by s^L) the mean
  // errors are 0.13, 0.19 and 0.15 px at octaves 1, 2 and 4, and 0.29 px at
  // octave 5 (the vertical scale errors of those levels times the shift).
  const StereoFeatureConfig config;
  const ShiftErrors e = MeanShiftErrorPerOctave(config);
  for (int level = 0; level < config.levels; ++level) {
    if (e.corners[level] < 300) continue;  // Too few for a mean.
    EXPECT_LT(std::abs(e.mean[level]), 0.1) << "octave " << level;
  }
  EXPECT_GT(e.corners[4], 300);
}

// Only the corners the grid bucketing keeps are described (on a pyramid
// built once, each level by a single-level ORB): every kept keypoint must be
// a corner OpenCV's multi-level detectAndCompute finds, with its descriptor,
// the strongest first.
TEST(StereoFeaturesTest, KeptCornersCarryOrbsOwnDescriptors) {
  std::mt19937 rng(3);
  const cv::Mat image =
      View(RenderWorld(640, 185, 9), 0.0, 613, 185, 2.0, &rng);
  StereoFeatureConfig config;
  const StereoCalibration calibration{353.5, 353.5, 306.0, 92.0, 0.54};
  const StereoFeatureExtractor extractor(config, calibration);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.DetectAndDescribe(image, &keypoints, &descriptors);
  auto orb = cv::ORB::create(2 * config.max_features,
                             static_cast<float>(config.scale_factor),
                             config.levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31,
                             config.fast_threshold);
  std::vector<cv::KeyPoint> all;
  cv::Mat all_descriptors;
  orb->detectAndCompute(image, cv::noArray(), all, all_descriptors);
  ASSERT_GT(keypoints.size(), 100u);
  ASSERT_LT(keypoints.size(), all.size());  // The bucketing dropped some.
  ASSERT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
  int octaves_seen = 0;
  std::vector<bool> octave_seen(config.levels, false);  // Levels < 8.
  for (size_t k = 0; k < keypoints.size(); ++k) {
    if (k > 0) {
      EXPECT_GE(keypoints[k - 1].response, keypoints[k].response);
    }
    // The same corner: octave, Harris response and angle (the position is
    // moved to the level's pixel centres).
    int found = -1;
    for (size_t j = 0; j < all.size() && found < 0; ++j) {
      if (all[j].octave == keypoints[k].octave &&
          all[j].response == keypoints[k].response &&
          all[j].angle == keypoints[k].angle)
        found = static_cast<int>(j);
    }
    ASSERT_GE(found, 0) << "keypoint " << k;
    EXPECT_EQ(cv::norm(descriptors.row(static_cast<int>(k)),
                       all_descriptors.row(found), cv::NORM_HAMMING),
              0.0)
        << "keypoint " << k << " at octave " << keypoints[k].octave;
    if (!octave_seen[keypoints[k].octave]) ++octaves_seen;
    octave_seen[keypoints[k].octave] = true;
  }
  EXPECT_GE(octaves_seen, 3);  // Corners of several levels, mixed.
}

// A rendered wall whose right half has a tenth of the contrast: FAST scores
// there fall below fast_threshold (12) but not below min_fast_threshold.
cv::Mat HalfFaintImage() {
  std::mt19937 rng(5);
  cv::Mat image = View(RenderWorld(640, 185, 4), 0.0, 613, 185, 0.0, &rng);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = image.cols / 2; x < image.cols; ++x) {
      uchar& p = image.at<uchar>(y, x);
      p = cv::saturate_cast<uchar>(128 + 0.1 * (p - 128));
    }
  }
  return image;
}

// Textured cells (of cell_size pixels, with a FAST corner of score >=
// min_fast_threshold at least 19 pixels, ORB's border, inside the image)
// that have no octave-0 keypoint, in the left and in the right half.
std::pair<int, int> CellsWithoutOctaveZero(const StereoFeatureConfig& config,
                                           const cv::Mat& image) {
  const StereoCalibration calibration{353.5, 353.5, 306.0, 92.0, 0.54};
  const StereoFeatureExtractor extractor(config, calibration);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.DetectAndDescribe(image, &keypoints, &descriptors);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(image, corners, config.min_fast_threshold, true);
  cv::KeyPointsFilter::runByImageBorder(corners, image.size(), 19);
  const int c = config.cell_size;
  std::pair<int, int> empty{0, 0};
  for (int y0 = 0; y0 + c <= image.rows; y0 += c) {
    for (int x0 = 0; x0 + c <= image.cols; x0 += c) {
      if (x0 < image.cols / 2 && x0 + c > image.cols / 2) continue;
      bool textured = false, found = false;
      for (const cv::KeyPoint& k : corners) {
        textured = textured || (k.pt.x >= x0 && k.pt.x < x0 + c &&
                                k.pt.y >= y0 && k.pt.y < y0 + c);
      }
      if (!textured) continue;
      for (const cv::KeyPoint& k : keypoints) {
        found = found || (k.octave == 0 && k.pt.x >= x0 && k.pt.x < x0 + c &&
                          k.pt.y >= y0 && k.pt.y < y0 + c);
      }
      if (!found) ++(x0 < image.cols / 2 ? empty.first : empty.second);
    }
  }
  return empty;
}

// The per-cell detection gives every textured cell corners at octave 0,
// the faint ones included (OpenCV's ORB keeps a level's strongest corners
// over the whole image: the faint half gets none at octave 0).
TEST(StereoFeaturesTest, GridFastGivesEveryTexturedCellOctaveZeroCorners) {
  const cv::Mat image = HalfFaintImage();
  StereoFeatureConfig config;
  const std::pair<int, int> orb = CellsWithoutOctaveZero(config, image);
  std::printf("ORB: cells without octave-0 corners %d left, %d right\n",
              orb.first, orb.second);
  EXPECT_GT(orb.second, 10);  // The mechanism the grid detection mends.
  config.grid_fast = true;
  const std::pair<int, int> grid = CellsWithoutOctaveZero(config, image);
  std::printf("grid: cells without octave-0 corners %d left, %d right\n",
              grid.first, grid.second);
  EXPECT_EQ(grid.first, 0);
  EXPECT_EQ(grid.second, 0);
}

TEST(StereoFeaturesTest, MinFastThresholdMustNotExceedFastThreshold) {
  StereoFeatureConfig config;
  std::string error;
  EXPECT_TRUE(ValidateStereoFeatureConfig(config, &error)) << error;
  config.min_fast_threshold = config.fast_threshold + 1;
  EXPECT_FALSE(ValidateStereoFeatureConfig(config, &error));
  EXPECT_NE(error.find("min_fast_threshold"), std::string::npos) << error;
  config.min_fast_threshold = 0;
  EXPECT_FALSE(ValidateStereoFeatureConfig(config, &error));
}

// The grid detection's corners at octave 0 are OpenCV's ORB corners of the
// same image (FAST at min_fast_threshold), with ORB's Harris response,
// orientation and descriptor.
TEST(StereoFeaturesTest, GridFastCornersCarryOrbsOwnAnglesAndDescriptors) {
  const cv::Mat image = HalfFaintImage();
  StereoFeatureConfig config;
  config.grid_fast = true;
  const StereoCalibration calibration{353.5, 353.5, 306.0, 92.0, 0.54};
  const StereoFeatureExtractor extractor(config, calibration);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.DetectAndDescribe(image, &keypoints, &descriptors);
  ASSERT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
  auto orb = cv::ORB::create(1000000, 1.2f, 1, 19, 0, 2, cv::ORB::HARRIS_SCORE,
                             31, config.min_fast_threshold);
  std::vector<cv::KeyPoint> all;
  cv::Mat all_descriptors;
  orb->detectAndCompute(image, cv::noArray(), all, all_descriptors);
  int compared = 0, octave_zero = 0;
  for (size_t k = 0; k < keypoints.size(); ++k) {
    if (k > 0) {
      EXPECT_GE(keypoints[k - 1].response, keypoints[k].response);
    }
    if (keypoints[k].octave != 0) continue;
    ++octave_zero;
    for (size_t j = 0; j < all.size(); ++j) {
      if (all[j].pt != keypoints[k].pt) continue;
      EXPECT_FLOAT_EQ(all[j].response, keypoints[k].response);
      EXPECT_EQ(all[j].angle, keypoints[k].angle) << "keypoint " << k;
      EXPECT_EQ(
          cv::norm(descriptors.row(static_cast<int>(k)),
                   all_descriptors.row(static_cast<int>(j)), cv::NORM_HAMMING),
          0.0)
          << "keypoint " << k;
      ++compared;
      break;
    }
  }
  std::printf("%d of %d octave-0 keypoints compared\n", compared, octave_zero);
  EXPECT_GT(octave_zero, 200);
  // A weak corner found on its cell alone may be one FAST's non-maximum
  // suppression over the whole image drops (a stronger neighbour across the
  // cell's edge).
  EXPECT_GE(compared, 0.98 * octave_zero);
}

}  // namespace
}  // namespace slam
