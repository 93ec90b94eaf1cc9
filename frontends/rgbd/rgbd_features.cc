#include "frontends/rgbd/rgbd_features.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <opencv2/calib3d.hpp>

#include "frontends/stereo/stereo_common.h"

namespace slam {

bool ValidateRgbdConfig(const RgbdConfig& config, std::string* error) {
  if (!(config.depth_factor > 0 && std::isfinite(config.depth_factor))) {
    *error = "depth_factor must be > 0 (depth image units per metre)";
    return false;
  }
  if (!(config.virtual_baseline > 0 && config.virtual_baseline < 10)) {
    *error = "virtual_baseline must be in (0, 10) m";
    return false;
  }
  if (config.depth_radius < 0 || config.depth_radius > 10 ||
      !(config.max_depth_step >= 0)) {
    *error = "depth_radius must be in [0, 10] and max_depth_step >= 0";
    return false;
  }
  if (!(config.min_depth >= 0 && config.max_depth > config.min_depth &&
        config.max_depth < 1e3)) {
    *error = "min_depth and max_depth must satisfy 0 <= min < max < 1000 m";
    return false;
  }
  return true;
}

StereoCalibration VirtualStereoCalibration(const RgbdCamera& camera,
                                           const RgbdConfig& config) {
  StereoCalibration c;
  c.fx = camera.fx;
  c.fy = camera.fy;
  c.cx = camera.cx;
  c.cy = camera.cy;
  c.baseline = config.virtual_baseline;
  return c;
}

double VirtualRightU(double u, double depth,
                     const StereoCalibration& virtual_camera,
                     const RgbdConfig& config) {
  if (!(depth >= config.min_depth && depth <= config.max_depth) || depth <= 0) {
    return StereoFeatureFrame::kNoRightCoordinate;
  }
  // May be negative (near points at the image's left edge): still a depth.
  return u - virtual_camera.fx * virtual_camera.baseline / depth;
}

RgbdFeatureExtractor::RgbdFeatureExtractor(const StereoFeatureConfig& features,
                                           const RgbdCamera& camera,
                                           const RgbdConfig& config)
    : camera_(camera),
      config_(config),
      calibration_(VirtualStereoCalibration(camera, config)),
      orb_(features, calibration_) {
  k_ = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy,
        camera.cy, 0, 0, 1);
  distortion_ = (cv::Mat_<double>(1, 5) << camera.k1, camera.k2, camera.p1,
                 camera.p2, camera.k3);
}

std::vector<cv::Point2f> RgbdFeatureExtractor::Undistort(
    const std::vector<cv::KeyPoint>& keypoints) const {
  std::vector<cv::Point2f> points;
  points.reserve(keypoints.size());
  for (const cv::KeyPoint& k : keypoints) points.push_back(k.pt);
  if (points.empty() || !camera_.HasDistortion()) return points;
  std::vector<cv::Point2f> undistorted;
  cv::undistortPoints(points, undistorted, k_, distortion_, cv::noArray(), k_);
  return undistorted;
}

double RgbdFeatureExtractor::DepthAt(const cv::Mat& depth, int col,
                                     int row) const {
  if (col < 0 || row < 0 || col >= depth.cols || row >= depth.rows) return 0.0;
  const double z = depth.at<float>(row, col);
  if (!(z > 0.0) || config_.max_depth_step <= 0.0) return z;
  const int r = config_.depth_radius;
  for (int y = std::max(0, row - r); y <= std::min(depth.rows - 1, row + r);
       ++y) {
    const float* line = depth.ptr<float>(y);
    for (int x = std::max(0, col - r); x <= std::min(depth.cols - 1, col + r);
         ++x) {
      if (!(std::abs(line[x] - z) <= config_.max_depth_step * z)) return 0.0;
    }
  }
  return z;
}

StereoFeatureFrame RgbdFeatureExtractor::Measure(
    const std::vector<cv::KeyPoint>& keypoints, const cv::Mat& descriptors,
    const cv::Mat& depth) const {
  const std::vector<cv::Point2f> undistorted = Undistort(keypoints);
  StereoFeatureFrame frame;
  std::vector<int> rows;
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point2f& p = undistorted[i];
    if (!(p.x >= 0 && p.y >= 0 && p.x <= depth.cols - 1 &&
          p.y <= depth.rows - 1)) {
      continue;
    }
    const int col = static_cast<int>(std::lround(keypoints[i].pt.x));
    const int row = static_cast<int>(std::lround(keypoints[i].pt.y));
    const double z = DepthAt(depth, col, row);
    cv::KeyPoint k = keypoints[i];
    k.pt = p;
    frame.keypoints.push_back(k);
    frame.u_right.push_back(VirtualRightU(p.x, z, calibration_, config_));
    rows.push_back(static_cast<int>(i));
  }
  frame.descriptors.create(static_cast<int>(rows.size()), descriptors.cols,
                           descriptors.type());
  for (size_t r = 0; r < rows.size(); ++r) {
    descriptors.row(rows[r]).copyTo(frame.descriptors.row(static_cast<int>(r)));
  }
  return frame;
}

StereoFeatureFrame RgbdFeatureExtractor::Extract(
    const cv::Mat& grey, const cv::Mat& depth,
    StereoFeatureTimings* timings) const {
  auto start = std::chrono::steady_clock::now();
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb_.DetectAndDescribe(grey, &keypoints, &descriptors);
  timings->features_ms = stereo::MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  StereoFeatureFrame frame = Measure(keypoints, descriptors, depth);
  timings->matching_ms = stereo::MillisecondsSince(start);
  return frame;
}

}  // namespace slam
