#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_common.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <thread>

#include <opencv2/core/hal/hal.hpp>
#include <opencv2/imgproc.hpp>

#include "frontends/image_io.h"

namespace slam {
namespace {

// Border (pixels) of the image without keypoints, on every pyramid level.
constexpr int kOrbEdgeThreshold = 19;

using stereo::Hamming;

// Sum of absolute differences between the left patch at (ul, v) and the
// right patch at (ur, v), both brightness-normalised by their centre pixel;
// -1 if a patch leaves the image.
int PatchSad(const cv::Mat& left, const cv::Mat& right, int ul, int ur, int v,
             int r) {
  if (v - r < 0 || v + r >= left.rows || ul - r < 0 || ul + r >= left.cols ||
      ur - r < 0 || ur + r >= right.cols) {
    return -1;
  }
  const int cl = left.at<uchar>(v, ul);
  const int cr = right.at<uchar>(v, ur);
  int sad = 0;
  for (int dv = -r; dv <= r; ++dv) {
    const uchar* pl = left.ptr<uchar>(v + dv) + ul - r;
    const uchar* pr = right.ptr<uchar>(v + dv) + ur - r;
    for (int du = 0; du <= 2 * r; ++du) {
      sad += std::abs((pl[du] - cl) - (pr[du] - cr));
    }
  }
  return sad;
}

// The sub-pixel shift delta of the right patch centred at (ur + delta, v)
// that matches the left patch centred at (ul, v): Gauss-Newton on the sum of
// squared differences of the zero-mean patches, from *delta. Both patches are
// sampled by linear interpolation, the left at ul - delta / 2 and the right
// at ur + delta / 2, so that both are blurred alike by the interpolation
// (interpolating only the right one pulls the estimate towards whole
// pixels, as the parabola through SAD values does). False if a patch would
// leave the image, the normal equations are singular or |delta| > 1.
bool RefineShift(const cv::Mat& left, const cv::Mat& right, int ul, int ur,
                 int v, int r, double* delta) {
  if (v - r < 0 || v + r >= left.rows || ul - r - 1 < 0 ||
      ul + r + 2 >= left.cols || ur - r - 1 < 0 || ur + r + 2 >= right.cols) {
    return false;
  }
  const int n = (2 * r + 1) * (2 * r + 1);
  std::vector<double> lv(n), lg(n), rv(n), rg(n);
  // Linear interpolation of row `row` at x0 + c + shift, c in [-r, r].
  auto sample = [r](const uchar* row, int x0, double shift, double* value,
                    double* gradient) {
    const int base = static_cast<int>(std::floor(shift));
    const double a = shift - base;
    for (int c = -r; c <= r; ++c) {
      const int x = x0 + c + base;
      value[c + r] = (1.0 - a) * row[x] + a * row[x + 1];
      gradient[c + r] = row[x + 1] - row[x];
    }
  };
  for (int iteration = 0; iteration < 10; ++iteration) {
    const double d = std::clamp(*delta, -1.0, 1.0);
    for (int dv = -r; dv <= r; ++dv) {
      const int k = (dv + r) * (2 * r + 1);
      sample(left.ptr<uchar>(v + dv), ul, -0.5 * d, &lv[k], &lg[k]);
      sample(right.ptr<uchar>(v + dv), ur, 0.5 * d, &rv[k], &rg[k]);
    }
    double ml = 0, mr = 0, mlg = 0, mrg = 0;
    for (int k = 0; k < n; ++k) {
      ml += lv[k];
      mr += rv[k];
      mlg += lg[k];
      mrg += rg[k];
    }
    ml /= n;
    mr /= n;
    mlg /= n;
    mrg /= n;
    double jtj = 0, jte = 0;
    for (int k = 0; k < n; ++k) {
      const double e = (lv[k] - ml) - (rv[k] - mr);
      // d e / d delta: the left moves by -1/2, the right by +1/2.
      const double j = -0.5 * (lg[k] - mlg) - 0.5 * (rg[k] - mrg);
      jtj += j * j;
      jte += j * e;
    }
    if (!(jtj > 1e-9)) return false;
    const double step = -jte / jtj;
    *delta = d + step;
    if (std::abs(*delta) > 1.0) return false;
    if (std::abs(step) < 1e-4) break;
  }
  return true;
}

// The full-image position of an ORB keypoint (see DetectAndDescribe).
cv::Point2f LevelToImage(const cv::KeyPoint& k, const cv::Size& size,
                         double scale_factor) {
  if (k.octave <= 0) return k.pt;
  // The level's scale and size as OpenCV's ORB computes them (float).
  const float scale = static_cast<float>(std::pow(scale_factor, k.octave));
  const int width = cvRound(size.width / scale);
  const int height = cvRound(size.height / scale);
  const double x = k.pt.x / scale, y = k.pt.y / scale;
  return cv::Point2f(
      static_cast<float>((x + 0.5) * size.width / width - 0.5),
      static_cast<float>((y + 0.5) * size.height / height - 0.5));
}

// OpenCV's ORB Harris response (orb.cpp, HarrisResponses: 7 x 7 block,
// k = 0.04, Sobel gradients, the same scaling) at (x, y) of a level image;
// (x, y) at least 4 pixels inside it.
float OrbHarrisResponse(const cv::Mat& img, int x, int y) {
  constexpr int kBlock = 7;
  constexpr float kHarrisK = 0.04f;
  const int r = kBlock / 2;
  const int step = static_cast<int>(img.step);
  const float scale = 1.f / ((1 << 2) * kBlock * 255.f);
  const float scale_sq_sq = scale * scale * scale * scale;
  int a = 0, b = 0, c = 0;
  for (int i = 0; i < kBlock; ++i) {
    const uchar* row = img.ptr<uchar>(y - r + i) + x - r;
    for (int j = 0; j < kBlock; ++j) {
      const uchar* p = row + j;
      const int ix = (p[1] - p[-1]) * 2 + (p[-step + 1] - p[-step - 1]) +
                     (p[step + 1] - p[step - 1]);
      const int iy = (p[step] - p[-step]) * 2 + (p[step - 1] - p[-step - 1]) +
                     (p[step + 1] - p[-step + 1]);
      a += ix * ix;
      b += iy * iy;
      c += ix * iy;
    }
  }
  return (static_cast<float>(a) * b - static_cast<float>(c) * c -
          kHarrisK * (static_cast<float>(a) + b) *
              (static_cast<float>(a) + b)) *
         scale_sq_sq;
}

// OpenCV's ORB orientation (orb.cpp, ICAngles): the intensity centroid of
// the circular patch of radius 15 around (x, y), which is at least 15
// pixels inside the level image; degrees, as fastAtan2.
float OrbAngle(const cv::Mat& img, int x, int y) {
  constexpr int kHalf = 15;  // patchSize 31 / 2.
  static const std::vector<int> u_max = [] {
    std::vector<int> u(kHalf + 2);
    const int vmax = cvFloor(kHalf * std::sqrt(2.f) / 2 + 1);
    const int vmin = cvCeil(kHalf * std::sqrt(2.f) / 2);
    for (int v = 0; v <= vmax; ++v)
      u[v] = cvRound(std::sqrt(static_cast<double>(kHalf) * kHalf - v * v));
    for (int v = kHalf, v0 = 0; v >= vmin; --v) {  // Symmetric, as ORB's.
      while (u[v0] == u[v0 + 1]) ++v0;
      u[v] = v0;
      ++v0;
    }
    return u;
  }();
  const int step = static_cast<int>(img.step1());
  const uchar* center = &img.at<uchar>(y, x);
  int m_01 = 0, m_10 = 0;
  for (int u = -kHalf; u <= kHalf; ++u) m_10 += u * center[u];
  for (int v = 1; v <= kHalf; ++v) {
    int v_sum = 0;
    const int d = u_max[v];
    for (int u = -d; u <= d; ++u) {
      const int plus = center[u + v * step], minus = center[u - v * step];
      v_sum += plus - minus;
      m_10 += u * (plus + minus);
    }
    m_01 += v * v_sum;
  }
  return cv::fastAtan2(static_cast<float>(m_01), static_cast<float>(m_10));
}

}  // namespace

bool ValidateStereoFeatureConfig(const StereoFeatureConfig& c,
                                 std::string* error) {
  auto fail = [&](const char* message) {
    *error = message;
    return false;
  };
  if (c.max_features < 10 || c.max_features > 100000)
    return fail("max_features must be in [10, 100000]");
  if (!(c.scale_factor > 1.0 && c.scale_factor <= 2.0))
    return fail("scale_factor must be in (1, 2]");
  if (c.levels < 1 || c.levels > 16) return fail("levels must be in [1, 16]");
  if (c.fast_threshold < 1 || c.fast_threshold > 255)
    return fail("fast_threshold must be in [1, 255]");
  if (c.min_fast_threshold < 1 || c.min_fast_threshold > c.fast_threshold)
    return fail("min_fast_threshold must be in [1, fast_threshold]");
  if (c.cell_size < 4 || c.max_per_cell < 1)
    return fail("cell_size must be >= 4 and max_per_cell >= 1");
  if (!(c.row_tolerance >= 0 && c.row_tolerance < 100))
    return fail("row_tolerance must be in [0, 100)");
  if (!(c.min_disparity >= 0) || !(c.max_disparity_fraction > 0) ||
      !(c.max_disparity_fraction <= 1))
    return fail("min_disparity must be >= 0, max_disparity_fraction in (0, 1]");
  if (c.max_descriptor_distance < 0 || c.max_descriptor_distance > 256)
    return fail("max_descriptor_distance must be in [0, 256]");
  if (!(c.ratio > 0 && c.ratio <= 1)) return fail("ratio must be in (0, 1]");
  if (c.patch_radius < 1 || c.patch_radius > 20 || c.search_radius < 1 ||
      c.search_radius > 50)
    return fail("patch_radius must be in [1, 20], search_radius in [1, 50]");
  if (!(c.max_depth_baselines > 1))
    return fail("max_depth_baselines must be > 1");
  return true;
}

StereoFeatureExtractor::StereoFeatureExtractor(
    const StereoFeatureConfig& config, const StereoCalibration& calibration)
    : config_(config), calibration_(calibration) {
  // Detect more corners than kept: the bucketing below chooses among them.
  // OpenCV's multi-level ORB (orb.cpp, computeKeyPoints) asks each level
  // for a share of them that falls geometrically with the level, in float
  // arithmetic as here; each level is then an ORB of one level asked for
  // that share, on that level's image.
  const int total = 2 * config.max_features;
  const float scale_factor = static_cast<float>(config.scale_factor);
  const float factor = static_cast<float>(1.0 / scale_factor);
  float share =
      total * (1 - factor) /
      (1 - static_cast<float>(std::pow(static_cast<double>(factor),
                                       static_cast<double>(config.levels))));
  int sum = 0;
  for (int level = 0; level < config.levels; ++level) {
    int n = std::max(total - sum, 0);
    if (level < config.levels - 1) {
      n = cvRound(share);
      sum += n;
      share *= factor;
    }
    level_orbs_.push_back(cv::ORB::create(
        n, scale_factor, /*nlevels=*/1, kOrbEdgeThreshold, /*firstLevel=*/0,
        /*WTA_K=*/2, cv::ORB::HARRIS_SCORE, /*patchSize=*/31,
        config.fast_threshold));
    level_scales_.push_back(static_cast<float>(std::pow(
        static_cast<double>(scale_factor), static_cast<double>(level))));
  }
}

int StereoFeatureExtractor::MinImageSide() const {
  return OrbMinImageSide(config_.levels, config_.scale_factor,
                         kOrbEdgeThreshold);
}

void StereoFeatureExtractor::DetectAndDescribe(
    const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints,
    cv::Mat* descriptors) const {
  // The image pyramid, built once as OpenCV's ORB builds it (each level the
  // INTER_LINEAR_EXACT resize of the one above, its size rounded from the
  // float scale). ORB's detect() and then compute() on the kept corners
  // built it twice, which cost RGB-D (that keeps most corners) 12 % of its
  // feature time. Each level's single-level ORB finds the corners (FAST,
  // Harris response, orientation) and describes them on that level's image
  // exactly as the multi-level ORB does on its pyramid buffer: same pixels,
  // same border (reflected, 23 pixels), same blur.
  keypoints->clear();
  *descriptors = cv::Mat();
  if (image.empty()) return;  // As ORB: no corners.
  const int levels = static_cast<int>(level_orbs_.size());
  std::vector<cv::Mat> pyramid(levels);
  std::vector<cv::KeyPoint> all;      // In image coordinates, as ORB's.
  std::vector<cv::Point2f> at_level;  // The same corners' level positions.
  for (int level = 0; level < levels; ++level) {
    const float scale = level_scales_[level];
    if (level == 0) {
      pyramid[0] = image;
    } else {
      cv::resize(
          pyramid[level - 1], pyramid[level],
          cv::Size(cvRound(image.cols / scale), cvRound(image.rows / scale)), 0,
          0, cv::INTER_LINEAR_EXACT);
    }
    if (config_.grid_fast) continue;  // DetectGrid below.
    std::vector<cv::KeyPoint> found;
    level_orbs_[level]->detect(pyramid[level], found);
    for (cv::KeyPoint k : found) {
      at_level.push_back(k.pt);
      k.octave = level;
      k.size = 31 * scale;
      k.pt *= scale;
      all.push_back(k);
    }
  }
  if (config_.grid_fast) DetectGrid(pyramid, &all, &at_level);
  // Grid bucketing: the strongest max_per_cell per cell, then the strongest
  // overall up to max_features. Only the kept corners are described: ORB
  // detects 2 max_features corners, of which the bucketing keeps a fraction
  // (KITTI 06: 748 of 4600 at half, 1468 of 6000 at full resolution), and
  // describing them all was about a third of ORB's time. The descriptors
  // are those detectAndCompute gives the same corners.
  const int cols = (image.cols + config_.cell_size - 1) / config_.cell_size;
  std::vector<int> order(all.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return all[a].response > all[b].response; });
  std::map<int, int> per_cell;
  std::vector<int> kept;
  for (int i : order) {
    const int cell = static_cast<int>(all[i].pt.y) / config_.cell_size * cols +
                     static_cast<int>(all[i].pt.x) / config_.cell_size;
    if (per_cell[cell]++ >= config_.max_per_cell) continue;
    kept.push_back(i);
    if (static_cast<int>(kept.size()) >= config_.max_features) break;
  }
  // The kept corners by level (in the bucketing's order within a level),
  // described on their level; the strongest first again (ties by level), the
  // order ORB's compute() on all kept corners gave.
  std::vector<int> by_level;
  std::vector<cv::Mat> level_rows;  // Descriptor of by_level[k].
  for (int level = 0; level < levels; ++level) {
    std::vector<int> ids;
    std::vector<cv::KeyPoint> corners;
    for (int i : kept) {
      if (all[i].octave != level) continue;
      ids.push_back(i);
      corners.push_back(all[i]);
      corners.back().pt = at_level[i];
      corners.back().octave = 0;
    }
    if (corners.empty()) continue;
    if (config_.grid_fast) {  // Oriented here, only the kept corners.
      for (size_t k = 0; k < corners.size(); ++k) {
        corners[k].angle = OrbAngle(pyramid[level], cvRound(corners[k].pt.x),
                                    cvRound(corners[k].pt.y));
        all[ids[k]].angle = corners[k].angle;
      }
    }
    cv::Mat level_descriptors;
    level_orbs_[level]->compute(pyramid[level], corners, level_descriptors);
    // compute() drops a corner too close to the border; these were found
    // on the same level image with the same border, so none is, but the
    // rows are matched to the corners by position all the same.
    size_t next = 0;
    for (size_t r = 0; r < corners.size(); ++r) {
      while (next < ids.size() && at_level[ids[next]] != corners[r].pt) ++next;
      if (next == ids.size()) break;
      by_level.push_back(ids[next++]);
      level_rows.push_back(level_descriptors.row(static_cast<int>(r)));
    }
  }
  std::vector<int> strongest(by_level.size());
  for (size_t i = 0; i < strongest.size(); ++i)
    strongest[i] = static_cast<int>(i);
  std::stable_sort(strongest.begin(), strongest.end(), [&](int a, int b) {
    return all[by_level[a]].response > all[by_level[b]].response;
  });
  *descriptors = cv::Mat(static_cast<int>(by_level.size()), 32, CV_8U);
  for (size_t k = 0; k < strongest.size(); ++k) {
    keypoints->push_back(all[by_level[strongest[k]]]);
    level_rows[strongest[k]].copyTo(descriptors->row(static_cast<int>(k)));
    keypoints->back().pt =
        LevelToImage(keypoints->back(), image.size(), config_.scale_factor);
  }
}

void StereoFeatureExtractor::DetectGrid(
    const std::vector<cv::Mat>& pyramid, std::vector<cv::KeyPoint>* all,
    std::vector<cv::Point2f>* at_level) const {
  // FAST at fast_threshold over each level; a cell (cell_size image pixels,
  // the bucketing's cells) without a corner there is searched again at
  // min_fast_threshold (FAST on the cell with a 3-pixel margin, the radius
  // of its circle). Each cell of each level keeps its max_per_cell
  // strongest by FAST score.
  const int cell = config_.cell_size;
  const int cols = (pyramid[0].cols + cell - 1) / cell;
  const int rows = (pyramid[0].rows + cell - 1) / cell;
  for (size_t level = 0; level < pyramid.size(); ++level) {
    const cv::Mat& image = pyramid[level];
    const float scale = level_scales_[level];
    auto cell_of = [&](const cv::Point2f& p) {
      const int cx = std::min(cols - 1, static_cast<int>(p.x * scale) / cell);
      const int cy = std::min(rows - 1, static_cast<int>(p.y * scale) / cell);
      return static_cast<size_t>(cy) * cols + cx;
    };
    std::vector<cv::KeyPoint> found;
    cv::FAST(image, found, config_.fast_threshold, /*nonmaxSuppression=*/true);
    cv::KeyPointsFilter::runByImageBorder(found, image.size(),
                                          kOrbEdgeThreshold);
    std::vector<std::vector<int>> in_cell(static_cast<size_t>(cols) * rows);
    for (size_t i = 0; i < found.size(); ++i) {
      in_cell[cell_of(found[i].pt)].push_back(static_cast<int>(i));
    }
    // The part of each empty cell inside the level's border, searched at
    // the lower threshold.
    const cv::Rect inside(kOrbEdgeThreshold, kOrbEdgeThreshold,
                          image.cols - 2 * kOrbEdgeThreshold,
                          image.rows - 2 * kOrbEdgeThreshold);
    if (config_.min_fast_threshold < config_.fast_threshold &&
        inside.width > 0 && inside.height > 0) {
      for (int cy = 0; cy < rows; ++cy) {
        for (int cx = 0; cx < cols; ++cx) {
          const size_t c = static_cast<size_t>(cy) * cols + cx;
          if (!in_cell[c].empty()) continue;
          const int x0 = static_cast<int>(std::ceil(cx * cell / scale));
          const int y0 = static_cast<int>(std::ceil(cy * cell / scale));
          const int x1 = static_cast<int>(std::ceil((cx + 1) * cell / scale));
          const int y1 = static_cast<int>(std::ceil((cy + 1) * cell / scale));
          const cv::Rect area =
              cv::Rect(x0, y0, x1 - x0, y1 - y0) & inside;  // Whole pixels.
          if (area.width <= 0 || area.height <= 0) continue;
          const cv::Rect search(area.x - 3, area.y - 3, area.width + 6,
                                area.height + 6);
          std::vector<cv::KeyPoint> weak;
          cv::FAST(image(search), weak, config_.min_fast_threshold, true);
          for (cv::KeyPoint& k : weak) {
            k.pt.x += search.x;
            k.pt.y += search.y;
            if (!area.contains(cv::Point(cvRound(k.pt.x), cvRound(k.pt.y))) ||
                cell_of(k.pt) != c) {
              continue;
            }
            in_cell[c].push_back(static_cast<int>(found.size()));
            found.push_back(k);
          }
        }
      }
    }
    for (std::vector<int>& ids : in_cell) {
      if (ids.empty()) continue;
      const size_t n =
          std::min(ids.size(), static_cast<size_t>(config_.max_per_cell));
      std::partial_sort(
          ids.begin(), ids.begin() + n, ids.end(),
          [&](int a, int b) { return found[a].response > found[b].response; });
      for (size_t t = 0; t < n; ++t) {
        cv::KeyPoint k = found[ids[t]];
        at_level->push_back(k.pt);
        k.response = OrbHarrisResponse(image, cvRound(k.pt.x), cvRound(k.pt.y));
        k.octave = static_cast<int>(level);
        k.size = 31 * scale;
        k.pt *= scale;
        all->push_back(k);
      }
    }
  }
}

void StereoFeatureExtractor::MatchStereo(
    const cv::Mat& left, const cv::Mat& right,
    const std::vector<cv::KeyPoint>& left_keypoints,
    const cv::Mat& left_descriptors,
    const std::vector<cv::KeyPoint>& right_keypoints,
    const cv::Mat& right_descriptors, std::vector<double>* u_right) const {
  const StereoFeatureConfig& c = config_;
  u_right->assign(left_keypoints.size(),
                  StereoFeatureFrame::kNoRightCoordinate);
  // Right keypoints by row band.
  const int rows = right.rows;
  std::vector<std::vector<int>> by_row(rows);
  for (size_t j = 0; j < right_keypoints.size(); ++j) {
    const cv::KeyPoint& k = right_keypoints[j];
    const double r = c.row_tolerance * std::pow(c.scale_factor, k.octave);
    const int lo = std::max(0, static_cast<int>(std::floor(k.pt.y - r)));
    const int hi = std::min(rows - 1, static_cast<int>(std::ceil(k.pt.y + r)));
    for (int v = lo; v <= hi; ++v) by_row[v].push_back(static_cast<int>(j));
  }
  const double max_disparity = c.max_disparity_fraction * left.cols;
  const double min_depth_disparity = calibration_.fx / c.max_depth_baselines;
  // Best left keypoint per right keypoint (distance, left index).
  std::vector<std::pair<int, int>> owner(right_keypoints.size(),
                                         {std::numeric_limits<int>::max(), -1});
  std::vector<int> best_right(left_keypoints.size(), -1);
  for (size_t i = 0; i < left_keypoints.size(); ++i) {
    const cv::KeyPoint& kl = left_keypoints[i];
    const int v = static_cast<int>(std::lround(kl.pt.y));
    if (v < 0 || v >= rows) continue;
    int best = std::numeric_limits<int>::max(), second = best, best_j = -1;
    for (int j : by_row[v]) {
      const cv::KeyPoint& kr = right_keypoints[j];
      if (std::abs(kr.octave - kl.octave) > 1) continue;
      const double d = kl.pt.x - kr.pt.x;
      if (d < c.min_disparity || d > max_disparity) continue;
      const int dist =
          Hamming(left_descriptors, static_cast<int>(i), right_descriptors, j);
      if (dist < best) {
        second = best;
        best = dist;
        best_j = j;
      } else if (dist < second) {
        second = dist;
      }
    }
    if (best_j < 0 || best > c.max_descriptor_distance) continue;
    if (second != std::numeric_limits<int>::max() && best >= c.ratio * second)
      continue;
    best_right[i] = best_j;
    if (best < owner[best_j].first) owner[best_j] = {best, static_cast<int>(i)};
  }
  for (size_t i = 0; i < left_keypoints.size(); ++i) {
    const int j = best_right[i];
    if (j < 0 || owner[j].second != static_cast<int>(i)) continue;
    const cv::KeyPoint& kl = left_keypoints[i];
    const int ul = static_cast<int>(std::lround(kl.pt.x));
    const int v = static_cast<int>(std::lround(kl.pt.y));
    const int ur0 = static_cast<int>(std::lround(right_keypoints[j].pt.x));
    const int w = c.search_radius;
    std::vector<int> sad(2 * w + 1, -1);
    int best_s = 0, best_sad = std::numeric_limits<int>::max();
    for (int s = -w; s <= w; ++s) {
      sad[s + w] = PatchSad(left, right, ul, ur0 + s, v, c.patch_radius);
      if (sad[s + w] >= 0 && sad[s + w] < best_sad) {
        best_sad = sad[s + w];
        best_s = s;
      }
    }
    if (best_sad == std::numeric_limits<int>::max() || best_s == -w ||
        best_s == w || sad[best_s + w - 1] < 0 || sad[best_s + w + 1] < 0) {
      continue;
    }
    const double s1 = sad[best_s + w - 1], s2 = sad[best_s + w],
                 s3 = sad[best_s + w + 1];
    const double denom = 2.0 * (s1 + s3 - 2.0 * s2);
    double delta = denom > 0 ? (s1 - s3) / denom : 0.0;
    if (std::abs(delta) > 1.0 || !RefineShift(left, right, ul, ur0 + best_s, v,
                                              c.patch_radius, &delta)) {
      continue;
    }
    const double disparity = ul - (ur0 + best_s + delta);
    if (!(disparity > 0) || disparity < min_depth_disparity ||
        disparity < c.min_disparity || disparity > max_disparity) {
      continue;
    }
    (*u_right)[i] = kl.pt.x - disparity;
  }
}

StereoFeatureFrame StereoFeatureExtractor::Extract(
    const StereoImages& images, StereoFeatureTimings* timings) const {
  StereoFeatureFrame frame;
  frame.index = images.index;
  frame.stamp = images.stamp;
  auto start = std::chrono::steady_clock::now();
  std::vector<cv::KeyPoint> right_keypoints;
  cv::Mat right_descriptors;
  // The two images on two threads.
  std::thread right([&] {
    DetectAndDescribe(images.right, &right_keypoints, &right_descriptors);
  });
  DetectAndDescribe(images.left, &frame.keypoints, &frame.descriptors);
  right.join();
  if (timings != nullptr)
    timings->features_ms = stereo::MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  MatchStereo(images.left, images.right, frame.keypoints, frame.descriptors,
              right_keypoints, right_descriptors, &frame.u_right);
  if (timings != nullptr)
    timings->matching_ms = stereo::MillisecondsSince(start);
  return frame;
}

}  // namespace slam
