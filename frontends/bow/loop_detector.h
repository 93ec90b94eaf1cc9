// Visual loop detection over keyframes, in the way DLoopDetector (Galvez-Lopez
// and Tardos 2012) does it. For each new keyframe:
//   1. its bag of words is scored against the database, leaving out the
//      `exclude_recent` keyframes just before it;
//   2. the scores are normalised by the score against the previous keyframe
//      (how alike two views of the same place are right now; the best over
//      the last `prior_keyframes`); when that prior score is below
//      `min_prior_score` (a blank or blurred view) nothing is detected;
//      candidates below `min_normalized_score` are dropped;
//   3. the remaining candidates are grouped into islands (keyframes at most
//      `max_island_gap` apart); the island with the largest summed score
//      wins and its best keyframe is the candidate;
//   4. temporal consistency: the winning islands of `min_consistent_queries`
//      queries (this one included), each at most `max_query_gap` keyframes
//      after the one before, must lie within `max_island_distance`
//      keyframes of each other;
//   5. geometric verification (geometric_verification.h): fundamental
//      matrix RANSAC for monocular keyframes, PnP-RANSAC for stereo ones
//      (which also gives the relative pose and its covariance).
// The defaults are DLoopDetector's published ones (alpha 0.3, k 3, 20
// excluded keyframes, 50 results, gaps of 3 / 3 / 2, fundamental matrix with
// 2 px, direct index two levels up), stated per keyframe instead of per
// second of a 1 Hz stream; descriptor matching and the inlier minimum are
// ORB-SLAM2's for ORB (ratio 0.75, at least 20 inliers) instead of
// DLoopDetector's (0.6, 12, chosen for BRIEF/SURF). README: figures.
// Every keyframe is then added to the database.
//
// Use in a stereo pipeline (one detector per run):
//   bow::Vocabulary vocabulary;           // Load(file) or Train(descriptors)
//   bow::LoopDetectorConfig config;       // or ReadLoopsConfig (apps/visual)
//   config.verification = bow::Verification::kStereoPnp;
//   config.camera = {fx, fy, cx, cy};     // left camera, rectified
//   bow::LoopDetector detector(&vocabulary, config);
//   per keyframe:
//     bow::LoopKeyframe kf{id, stamp, descriptors, keypoints, points};
//     const bow::LoopResult r = detector.Process(std::move(kf));
//     if (r.status == bow::LoopStatus::kAccepted)
//       // camera pose of r.candidate_id -> camera pose of r.query_id:
//       BetweenSE3Factor::Create(r.T_candidate_query.t, r.T_candidate_query.q,
//           sqrt of bow::BetweenSE3Information(r.covariance)), robust kernel.
// `points` are the stereo-triangulated keypoints in the keyframe's camera
// frame (NaN without depth); the covariance models pixel noise only, so a
// robust kernel (and the rejection of loops the optimisation disagrees
// with) stays necessary.
#ifndef SLAM_FRONTENDS_BOW_LOOP_DETECTOR_H_
#define SLAM_FRONTENDS_BOW_LOOP_DETECTOR_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/conventions.h"
#include "core/lie.h"
#include "frontends/bow/database.h"
#include "frontends/bow/geometric_verification.h"
#include "frontends/bow/vocabulary.h"

namespace slam::bow {

enum class Verification { kNone, kFundamental, kStereoPnp };

struct LoopDetectorConfig {
  // Keyframes just before the query that are never candidates (they look
  // alike because they are close in time, not because of a loop).
  int exclude_recent = 20;
  int max_query_results = 50;  // Database results considered per query.
  // The direct index groups features this many levels above the words
  // (descriptor matching compares only features under the same node).
  int direct_index_levels_up = 2;
  double min_prior_score = 0.005;  // Score against the previous keyframe.
  // The prior score is the best against this many previous keyframes
  // (DLoopDetector: 1; 2 keeps one blank keyframe from also blinding the
  // next query: 3 more loops of 44 on the rtabmap samples, see README).
  int prior_keyframes = 2;
  double min_normalized_score = 0.3;  // Acceptance threshold (alpha).
  int max_island_gap = 3;             // Keyframes, within one island.
  int min_consistent_queries = 3;     // Consecutive agreeing queries.
  int max_island_distance = 3;        // Keyframes, between their islands.
  int max_query_gap = 2;              // Keyframes between those queries.
  Verification verification = Verification::kFundamental;
  MatchingOptions matching;
  FundamentalVerificationOptions fundamental;
  StereoVerificationOptions stereo;
  PinholeCamera camera;  // Stereo verification only (left camera).
};

// One keyframe as the detector needs it. `points` (stereo verification only)
// holds, per keypoint, its 3D position in this keyframe's camera frame, or
// NaN where the keypoint has no depth.
struct LoopKeyframe {
  int64_t id = 0;
  TimeNs stamp = 0;
  cv::Mat descriptors;  // CV_8U, one 32-byte row per keypoint.
  std::vector<cv::KeyPoint> keypoints;
  std::vector<Eigen::Vector3d> points;
};

enum class LoopStatus {
  kTooEarly,            // Nothing old enough in the database.
  kLowPriorScore,       // The view does not even resemble the previous one.
  kNoCandidate,         // Nothing above min_normalized_score.
  kNotConsistent,       // Not (yet) temporally consistent.
  kVerificationFailed,  // Too few geometric inliers.
  kAccepted,
};
const char* LoopStatusName(LoopStatus status);

struct LoopResult {
  LoopStatus status = LoopStatus::kTooEarly;
  int64_t query_id = 0;
  int64_t candidate_id = -1;  // Keyframe id of the candidate (if any).
  int64_t island_first = -1, island_last = -1;  // Keyframe ids.
  double score = 0.0;                           // L1 score of the candidate.
  double normalized_score = 0.0;                // score / prior score.
  int consistent_queries = 0;
  int matches = 0;  // Descriptor matches given to the verification.
  // Time of the bag-of-words transform and the database query, ms.
  double database_ms = 0.0;
  int inliers = 0;
  // Stereo verification: query camera -> candidate camera, and covariance
  // (tangent rho, phi; right perturbation).
  bool has_pose = false;
  Pose3 T_candidate_query;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

// The fewest keyframes among which a loop can be found: a query's
// candidates are the keyframes more than exclude_recent before it, so with
// fewer every query is kTooEarly, whatever the images (callers may skip the
// vocabulary and the detection then: the result is the same).
int MinKeyframesForALoop(const LoopDetectorConfig& config);

class LoopDetector {
 public:
  // The vocabulary must outlive the detector.
  LoopDetector(const Vocabulary* vocabulary, const LoopDetectorConfig& config);

  // Looks for a loop of `keyframe` with the earlier ones, then stores it.
  // Keyframes must arrive in time order; ids are the caller's.
  LoopResult Process(LoopKeyframe keyframe);

  size_t size() const { return keyframes_.size(); }
  const LoopKeyframe& keyframe(size_t index) const { return keyframes_[index]; }
  const LoopDetectorConfig& config() const { return config_; }

 private:
  bool Verify(const LoopKeyframe& query, const FeatureVector& query_features,
              size_t candidate, LoopResult* result) const;

  const Vocabulary* vocabulary_;
  LoopDetectorConfig config_;
  Database database_;
  std::vector<LoopKeyframe> keyframes_;  // By database entry.
  // Temporal consistency: the previous query's winning island (entries)
  // and how many consecutive queries agreed on it.
  int64_t last_query_ = -1;
  int64_t last_first_ = -1, last_last_ = -1;
  int consistent_ = 0;
};

}  // namespace slam::bow

#endif  // SLAM_FRONTENDS_BOW_LOOP_DETECTOR_H_
