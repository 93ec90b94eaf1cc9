#include "frontends/bow/geometric_verification.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace slam::bow {
namespace {

// Best and second-best distance of one query descriptor over candidates.
void MatchRange(const cv::Mat& query, const cv::Mat& candidate, int q,
                const std::vector<int>& candidates, int* best, int* best_index,
                int* second) {
  for (int c : candidates) {
    const int d =
        HammingDistance(query.ptr<uint8_t>(q), candidate.ptr<uint8_t>(c));
    if (d < *best) {
      *second = *best;
      *best = d;
      *best_index = c;
    } else if (d < *second) {
      *second = d;
    }
  }
}

}  // namespace

std::vector<cv::DMatch> MatchDescriptors(
    const cv::Mat& query, const cv::Mat& candidate,
    const FeatureVector* query_features,
    const FeatureVector* candidate_features, const MatchingOptions& options) {
  std::vector<cv::DMatch> best_of_candidate(
      candidate.rows, cv::DMatch(-1, -1, std::numeric_limits<float>::max()));
  auto consider = [&](int q, const std::vector<int>& candidates) {
    int best = std::numeric_limits<int>::max(), second = best, index = -1;
    MatchRange(query, candidate, q, candidates, &best, &index, &second);
    if (index < 0 || best > options.max_hamming) return;
    if (second != std::numeric_limits<int>::max() &&
        best > options.ratio * second)
      return;
    if (best < best_of_candidate[index].distance)
      best_of_candidate[index] = cv::DMatch(q, index, static_cast<float>(best));
  };
  if (query_features != nullptr && candidate_features != nullptr) {
    auto i = query_features->begin();
    auto j = candidate_features->begin();
    while (i != query_features->end() && j != candidate_features->end()) {
      if (i->first < j->first) {
        ++i;
      } else if (j->first < i->first) {
        ++j;
      } else {
        for (int q : i->second) consider(q, j->second);
        ++i;
        ++j;
      }
    }
  } else {
    std::vector<int> all(candidate.rows);
    for (int c = 0; c < candidate.rows; ++c) all[c] = c;
    for (int q = 0; q < query.rows; ++q) consider(q, all);
  }
  std::vector<cv::DMatch> matches;
  for (const cv::DMatch& m : best_of_candidate)
    if (m.queryIdx >= 0) matches.push_back(m);
  return matches;
}

Eigen::Matrix<double, 2, 6> ReprojectionJacobian(
    const Pose3& T_candidate_query, const Eigen::Vector3d& p_candidate,
    const PinholeCamera& camera) {
  // p_q = T^-1 p_c; with T <- T Exp(rho, phi):
  // p_q' ~ p_q - rho + [p_q]x phi.
  const Eigen::Vector3d p = T_candidate_query.Inverse() * p_candidate;
  Eigen::Matrix<double, 2, 3> d_pixel;
  const double iz = 1.0 / p.z();
  d_pixel << camera.fx * iz, 0.0, -camera.fx * p.x() * iz * iz, 0.0,
      camera.fy * iz, -camera.fy * p.y() * iz * iz;
  Eigen::Matrix<double, 3, 6> d_point;
  d_point.leftCols<3>() = -Eigen::Matrix3d::Identity();
  d_point.rightCols<3>() = Skew(p);
  return d_pixel * d_point;
}

StereoVerification VerifyStereoPnp(
    const std::vector<Eigen::Vector3d>& candidate_points,
    const std::vector<Eigen::Vector2d>& query_pixels,
    const PinholeCamera& camera, const StereoVerificationOptions& options) {
  StereoVerification result;
  const int n =
      static_cast<int>(std::min(candidate_points.size(), query_pixels.size()));
  result.matches = n;
  if (n < std::max(options.min_inliers, 6)) return result;
  std::vector<cv::Point3d> object(n);
  std::vector<cv::Point2d> image(n);
  for (int i = 0; i < n; ++i) {
    object[i] = cv::Point3d(candidate_points[i].x(), candidate_points[i].y(),
                            candidate_points[i].z());
    image[i] = cv::Point2d(query_pixels[i].x(), query_pixels[i].y());
  }
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0,
                      1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(object, image, k, cv::noArray(), rvec, tvec, false,
                            options.ransac_iterations,
                            static_cast<float>(options.reprojection_error_px),
                            options.confidence, inliers, cv::SOLVEPNP_EPNP);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok || static_cast<int>(inliers.size()) < options.min_inliers)
    return result;
  // Refine on the RANSAC inliers, then take the inliers of the refined pose.
  std::vector<cv::Point3d> in_object;
  std::vector<cv::Point2d> in_image;
  for (int i : inliers) {
    in_object.push_back(object[i]);
    in_image.push_back(image[i]);
  }
  cv::solvePnPRefineLM(in_object, in_image, k, cv::noArray(), rvec, tvec);
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d R_query_candidate;
  cv::cv2eigen(r, R_query_candidate);
  const Eigen::Vector3d t_query_candidate(
      tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  const Pose3 T_query_candidate(t_query_candidate,
                                Eigen::Quaterniond(R_query_candidate));
  result.T_candidate_query = T_query_candidate.Inverse();

  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  double sum_sq = 0.0;
  int count = 0;
  const double threshold_sq =
      options.reprojection_error_px * options.reprojection_error_px;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = T_query_candidate * candidate_points[i];
    if (p.z() <= 0.0) continue;
    const Eigen::Vector2d projected(camera.fx * p.x() / p.z() + camera.cx,
                                    camera.fy * p.y() / p.z() + camera.cy);
    const double e2 = (projected - query_pixels[i]).squaredNorm();
    if (e2 > threshold_sq) continue;
    sum_sq += e2;
    ++count;
    const Eigen::Matrix<double, 2, 6> j = ReprojectionJacobian(
        result.T_candidate_query, candidate_points[i], camera);
    information += j.transpose() * j;
  }
  result.inliers = count;
  if (count < options.min_inliers) return result;
  result.rms_px = std::sqrt(sum_sq / count);
  const double sigma_sq =
      std::max(count > 3 ? sum_sq / (2.0 * count - 6.0) : 0.0,
               options.min_pixel_sigma * options.min_pixel_sigma);
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(information / sigma_sq);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return result;
  result.covariance = ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
  result.covariance = 0.5 * (result.covariance + result.covariance.transpose());
  result.success = result.covariance.allFinite();
  return result;
}

Eigen::Matrix<double, 6, 6> BetweenSE3Information(
    const Eigen::Matrix<double, 6, 6>& covariance) {
  Eigen::Matrix<double, 6, 1> j;
  j << 1.0, 1.0, 1.0, 0.5, 0.5, 0.5;
  const Eigen::Matrix<double, 6, 6> c =
      j.asDiagonal() * covariance * j.asDiagonal();
  Eigen::Matrix<double, 6, 6> information =
      c.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
  return 0.5 * (information + information.transpose());
}

FundamentalVerification VerifyFundamental(
    const std::vector<cv::Point2f>& query_pixels,
    const std::vector<cv::Point2f>& candidate_pixels,
    const FundamentalVerificationOptions& options) {
  FundamentalVerification result;
  const size_t n = std::min(query_pixels.size(), candidate_pixels.size());
  result.matches = static_cast<int>(n);
  if (n < 8 || static_cast<int>(n) < options.min_inliers) return result;
  std::vector<cv::Point2f> q(query_pixels.begin(), query_pixels.begin() + n);
  std::vector<cv::Point2f> c(candidate_pixels.begin(),
                             candidate_pixels.begin() + n);
  std::vector<uchar> mask;
  cv::Mat f;
  try {
    // points1 = candidate, points2 = query: x_query^T F x_candidate = 0.
    f = cv::findFundamentalMat(c, q, cv::FM_RANSAC, options.epipolar_error_px,
                               options.confidence, mask);
  } catch (const cv::Exception&) {
    return result;
  }
  if (f.rows != 3 || f.cols != 3) return result;
  result.fundamental = f;
  result.inliers = static_cast<int>(std::count(mask.begin(), mask.end(), 1));
  result.success = result.inliers >= options.min_inliers;
  return result;
}

}  // namespace slam::bow
