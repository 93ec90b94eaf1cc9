// Loop closing for the stereo visual odometry (stereo_odometry.h), run over
// its keyframes once the sequence is processed (offline batch use):
//
//  1. Place recognition: every keyframe, in order, goes through the
//     bag-of-words loop detector (frontends/bow/loop_detector.h: database
//     query without the recent keyframes, scores normalised by the previous
//     keyframes', islands, temporal consistency) and stereo verification
//     (PnP-RANSAC of the candidate's stereo points against the query's
//     keypoints), which gives T_candidate_query and its covariance.
//  2. Pose graph: the keyframes joined in order by the odometry's relative
//     poses (between factors whose covariance follows a drift model:
//     sigma = drift_translation * distance + min_sigma_translation, and the
//     same for the rotation in rad per metre; a camera that turns drifts with
//     the angle turned as well: + drift_translation_per_rad * angle and
//     + drift_rotation_per_rad * angle), and every verified loop as a
//     between factor with the verification's covariance and the robust
//     kernel `kernel`. Optimized (keyframe 0 fixed); a loop whose whitened
//     error chi2 exceeds reject_chi2 after the optimization is rejected,
//     removed, and the graph optimized again, until none is.
//  3. The correction: the keyframes move to the optimized poses and every
//     map point moves with the keyframe that created it; the accepted loops
//     enter the odometry's graph as between factors (with the kernel), so
//     that the final global bundle adjustment (StereoOdometry::Finish) keeps
//     them.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_LOOP_CLOSING_H_
#define SLAM_FRONTENDS_STEREO_STEREO_LOOP_CLOSING_H_

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "factors/robust_kernels.h"
#include "frontends/bow/loop_detector.h"
#include "frontends/bow/vocabulary.h"
#include "frontends/stereo/stereo_odometry.h"

namespace slam {

struct StereoLoopClosingConfig {
  bool enabled = true;
  double drift_translation = 0.01;      // m per m travelled.
  double min_sigma_translation = 0.01;  // m.
  double drift_rotation = 0.001;        // rad per m travelled.
  double min_sigma_rotation = 0.001;    // rad.
  // Drift per radian turned between keyframes (0: none). A hand-held camera
  // turning in place travels a few centimetres while it turns by tens of
  // degrees: by distance alone, 24 keyframes over 0.3 m of TUM fr1/rpy are
  // allowed 0.3 deg of rotation drift, and its true loops (5 deg of drift)
  // are rejected by the pose graph.
  double drift_translation_per_rad = 0.0;  // m per rad turned.
  double drift_rotation_per_rad = 0.0;     // rad per rad turned.
  RobustKernelSpec kernel{"cauchy", 1.0};
  double reject_chi2 = 22.46;  // 99.9 % of chi2 with 6 dof.
  int max_iterations = 100;    // Of each pose-graph optimization.
};

bool ValidateStereoLoopClosingConfig(const StereoLoopClosingConfig& config,
                                     std::string* error);

// Step 2's information of the odometry edge between two consecutive
// keyframes with relative pose `relative` (the drift model; for
// MakeBetweenSE3, factors/pose_factors.h).
Eigen::Matrix<double, 6, 6> LoopDriftInformation(
    const StereoLoopClosingConfig& config, const Pose3& relative);

struct StereoLoop {
  int64_t query_keyframe = 0, candidate_keyframe = 0;
  int64_t query_frame = 0, candidate_frame = 0;  // Frame indices.
  double score = 0.0;  // Normalised bag-of-words score.
  int inliers = 0;
  Pose3 relative;  // Verified T_candidate_query (camera frames).
  bool accepted = false;
  std::string reason;  // Why it was rejected.
};

struct StereoLoopClosingResult {
  std::vector<StereoLoop> loops;  // Verified or rejected, in query order.
  int detected = 0;               // Temporally consistent candidates.
  int accepted = 0;
  int rejected = 0;  // By the verification or by the optimization.
  double largest_correction = 0.0;  // m, of any keyframe.
};

// The keyframe detector input: descriptors, keypoints and the stereo points
// in the keyframe's camera frame (NaN without a stereo match).
bow::LoopKeyframe LoopKeyframeOf(const StereoFeatureFrame& frame,
                                 const StereoCalibration& calibration,
                                 int64_t id);

// Steps 1-3. `detector` is used as given but for the verification, which
// is set to stereo PnP with the odometry's camera. Progress lines (each
// accepted and rejected loop) go to `log` when not null.
bool CloseStereoLoops(const bow::Vocabulary& vocabulary,
                      const bow::LoopDetectorConfig& detector,
                      const StereoLoopClosingConfig& config,
                      const StereoCalibration& calibration,
                      StereoOdometry* odometry, StereoLoopClosingResult* result,
                      std::ostream* log, std::string* error);

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_LOOP_CLOSING_H_
