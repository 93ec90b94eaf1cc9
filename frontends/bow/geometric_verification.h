// Geometric verification of a loop candidate: descriptor matching between two
// keyframes (restricted to features under the same vocabulary node when the
// direct indices are given), then
//   - stereo: PnP-RANSAC (cv::solvePnPRansac + Levenberg-Marquardt refinement
//     on the inliers) of the candidate's 3D points, in its camera frame,
//     against the query's pixels: the relative pose T_candidate_query, the
//     inliers and a 6x6 covariance from the inliers' reprojection Jacobians;
//   - monocular: fundamental-matrix RANSAC (cv::findFundamentalMat).
// A candidate is accepted with at least `min_inliers` inliers.
#ifndef SLAM_FRONTENDS_BOW_GEOMETRIC_VERIFICATION_H_
#define SLAM_FRONTENDS_BOW_GEOMETRIC_VERIFICATION_H_

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/lie.h"
#include "frontends/bow/vocabulary.h"

namespace slam::bow {

struct PinholeCamera {
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
};

// Defaults: ORB-SLAM2's loop-closing matcher for ORB (distance <= 50,
// ratio 0.75) and its minimum of 20 geometric inliers.
struct MatchingOptions {
  int max_hamming = 50;  // Largest accepted descriptor distance (of 256).
  double ratio = 0.75;   // Best / second-best distance (Lowe's test).
};

// Matches each query descriptor to its nearest candidate descriptor (one to
// one: a candidate feature keeps its best query feature). With both direct
// indices, only features under the same node are compared. Returned
// DMatch: queryIdx into `query`, trainIdx into `candidate`.
std::vector<cv::DMatch> MatchDescriptors(
    const cv::Mat& query, const cv::Mat& candidate,
    const FeatureVector* query_features,
    const FeatureVector* candidate_features, const MatchingOptions& options);

struct StereoVerificationOptions {
  int min_inliers = 20;                // Accept with at least this many.
  double reprojection_error_px = 3.0;  // RANSAC inlier threshold.
  int ransac_iterations = 300;
  double confidence = 0.999;
  // Floor of the pixel noise used for the covariance (the noise is
  // estimated from the inlier residuals, sigma^2 = sum r^2 / (2n - 6)).
  double min_pixel_sigma = 0.5;
};

struct StereoVerification {
  bool success = false;
  int matches = 0;  // Correspondences given to RANSAC.
  int inliers = 0;
  Pose3 T_candidate_query;  // Query camera frame -> candidate camera frame.
  // Of T_candidate_query, tangent (rho, phi) with right perturbation
  // (core/conventions.h). Only the pixel noise is modelled, not the depth
  // uncertainty of the stereo points.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  double rms_px = 0.0;  // Reprojection RMS of the inliers.
};

// PnP on given correspondences: candidate_points[i] (candidate camera frame)
// is seen at query_pixels[i] in the query image.
StereoVerification VerifyStereoPnp(
    const std::vector<Eigen::Vector3d>& candidate_points,
    const std::vector<Eigen::Vector2d>& query_pixels,
    const PinholeCamera& camera, const StereoVerificationOptions& options);

// Derivative of the query pixel of point p_candidate with respect to the
// right perturbation (rho, phi) of T_candidate_query (2x6).
Eigen::Matrix<double, 2, 6> ReprojectionJacobian(
    const Pose3& T_candidate_query, const Eigen::Vector3d& p_candidate,
    const PinholeCamera& camera);

// The information matrix of a verified loop for the SE(3) between factor
// (factors/between_se3.h) with measurement Z = T_candidate_query, i =
// candidate, j = query. That factor's error is (t, quaternion vector) of
// Z^-1 X_i^-1 X_j, i.e. (rho, phi / 2) for a right perturbation (rho, phi)
// of Z, so its information is (J C J^T)^-1 with J = diag(1, 1, 1, 1/2, 1/2,
// 1/2) and C the covariance of StereoVerification / LoopResult.
Eigen::Matrix<double, 6, 6> BetweenSE3Information(
    const Eigen::Matrix<double, 6, 6>& covariance);

struct FundamentalVerificationOptions {
  int min_inliers = 20;
  double epipolar_error_px = 2.0;  // RANSAC threshold (distance to the line).
  double confidence = 0.99;
};

struct FundamentalVerification {
  bool success = false;
  int matches = 0;
  int inliers = 0;
  cv::Mat fundamental;  // 3x3, x_query^T F x_candidate = 0.
};

FundamentalVerification VerifyFundamental(
    const std::vector<cv::Point2f>& query_pixels,
    const std::vector<cv::Point2f>& candidate_pixels,
    const FundamentalVerificationOptions& options);

}  // namespace slam::bow

#endif  // SLAM_FRONTENDS_BOW_GEOMETRIC_VERIFICATION_H_
