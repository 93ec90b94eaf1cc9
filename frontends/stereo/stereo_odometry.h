// Stereo visual odometry: keyframes and map points as a bundle-adjustment
// graph (core/graph.h: Pose3 keyframes T_world_camera of the left camera,
// Point3 map points in the world frame, rectified stereo factors
// factors/stereo_projection.h and pinhole factors factors/reprojection.h),
// built from the features of each frame (stereo_features.h).
//
// Per frame (in order):
//  1. Prediction: the previous frame's pose composed with the last
//     inter-frame motion (constant velocity; identity for the second frame).
//  2. Local map: the points observed by the last local_map_keyframes
//     keyframes, and (track_last_frame), when the last frame is not a
//     keyframe, its close stereo keypoints that no map point explains, as
//     points for this frame's tracking only (ORB-SLAM2's visual-odometry
//     points): without them a frame is tracked against points ever further
//     from the keyframe that made them (two frames of travel doubled the
//     pose error on KITTI 06), and the next keyframe shares few points with
//     the last.
//  3. Matching by projection: each local point, projected with the
//     predicted pose, is matched to the frame's keypoint within
//     search_radius pixels (times 1.2^octave of the keypoint) with the
//     smallest Hamming distance, if at most max_descriptor_distance and
//     below match_ratio times the second smallest; for a stereo keypoint
//     the right image coordinate must agree as well. One point per
//     keypoint (the closest in descriptor wins).
//  4. Pose-only refinement: the frame pose minimizes the stereo (or, for
//     keypoints without a stereo match, monocular) reprojection errors of
//     the matches with a Huber kernel, in pose_rounds rounds; after each
//     round every match is classified by the chi2 test of its whitened
//     error (chi2_stereo for 3 dof, chi2_mono for 2) and only inliers
//     enter the next round (ORB-SLAM's PoseOptimization). Noise: the
//     keypoint pixel_sigma * 1.2^octave, the disparity disparity_sigma
//     (StereoInformation). Close and far (ORB-SLAM2's stereo rule): a
//     stereo keypoint deeper than close_depth_baselines baselines is a
//     monocular observation everywhere (tracking and bundle adjustment), as
//     its disparity, a few pixels, tells the depth only to within its
//     sub-pixel errors (a bias of 0.1 px is 1 % of depth at 5 px, and
//     scales the path by as much when such points dominate). A point made
//     from a far keypoint is unconfirmed: it is matched, and its matches
//     become keyframe observations, but it does not enter this refinement
//     until far_point_min_keyframes keyframes observe it with rays at least
//     min_parallax apart (the local bundle adjustment triangulates it from
//     their views) or a close stereo observation fixes its depth; with
//     far_points_wait false (the default) it is used at once, as a
//     monocular observation (it then mostly fixes rotation). Unconfirmed
//     points are removed before the global bundle adjustment.
//  5. Fallback when fewer than min_inliers matches survive: the frame's
//     descriptors are matched to the local map's by brute force (ratio
//     test), cv::solvePnPRansac estimates the pose from those 3D-2D pairs,
//     and steps 3-4 run again from it with search_radius / 2. If that fails
//     too the frame keeps the prediction (counted as lost) and becomes a
//     keyframe, so that the map restarts from its stereo points.
//  6. Keyframe decision, by need (ORB-SLAM2's rules without its idle
//     local-mapping condition): a new keyframe when the frame is lost, or
//     keyframe_max_frames frames passed since the last keyframe, or the
//     camera turned more than keyframe_rotation from it, or, once
//     keyframe_min_frames frames passed, when the inliers drop below
//     keyframe_tracked_ratio times the map points the last keyframe
//     observes, or when fewer than keyframe_close_tracked close points are
//     tracked while more than keyframe_new_close close stereo keypoints
//     could be added (new structure).
//  7. Keyframe: its inlier matches become factors (those to the last
//     frame's points do not: their keypoints become new points); with
//     keyframe_odometry, the chain of trackings since the last keyframe
//     (each frame's pose information from its matches, the points held:
//     the map's for the frame after the keyframe, the last frame's points'
//     for the others, composed to first order) becomes a relative-pose
//     factor between the two keyframes (factors/between_se3.h), so that
//     bundle adjustment does not override what the frames between them
//     tracked with the few points the two keyframes share. Its stereo
//     keypoints without a map point (closer than the feature extractor's
//     depth limit) become new map points, triangulated from the stereo pair
//     (the far ones unconfirmed, see step 4). A point that
//     min_point_observations keyframes do not observe by the time
//     cull_after_keyframes more keyframes exist is removed (an unconfirmed
//     point: a wrong stereo match, or a feature that did not repeat).
//  8. Local bundle adjustment over the last window_keyframes keyframes and
//     every point they observe (Schur complement, points eliminated first);
//     unconfirmed points seen by one keyframe only are left out (nothing
//     fixes their depth); the other keyframes that observe those points
//     enter held fixed, as
//     ORB-SLAM's local BA does (marginalizing them instead would turn
//     thousands of point observations into dense priors between the window's
//     poses at every keyframe). Observations that fail the chi2 test or lie
//     behind their camera afterwards are removed from the graph; points
//     left without observations are removed.
//  9. Finish: the points below min_point_observations are removed, then a
//     global bundle adjustment over every keyframe and point
//     (final_ba_iterations; 0: none), the first keyframe held fixed.
// 10. Output (FrameTrajectory): every frame's pose from its reference
//     keyframe (below); the positions of the frames between two keyframes
//     smoothed against the keyframes' path (between_acceleration_sigma) or
//     put on it (interpolate_between_keyframes).
//
// Every frame keeps its pose relative to its reference keyframe (the last
// keyframe when it was tracked), so that every frame gets a pose in the
// output trajectory after the keyframes move; with keyframe_odometry, what
// bundle adjustment changed in the next keyframe's pose against the
// tracking chain is spread along the frames between the two by their share
// of the frames (else the one step into the next keyframe takes all of it).
// With interpolate_between_keyframes a frame between two keyframes is put
// at its share of the way between them instead, its rotation kept (the
// keyframes' final poses, composed at output time).
//
// Local BA (step 8) includes the relative-pose factors of step 7 between
// the window's keyframes (the keyframe before the window held fixed).
//
// With local_mapping_thread (as ORB-SLAM's local mapping thread, but joined
// at a fixed point), step 8 of a keyframe solves on a second thread, on
// copies of the values it changes, and AddFrame returns at once; the next
// AddFrame (or Finish, WaitForLocalMapping) first waits for it and merges
// its result (the values, then the outlier observations removed and the
// points culled), so that the map, and the trajectory, are those of the
// run without the thread: what overlaps is the caller's work between the
// two calls (the next frame's feature extraction and image decoding,
// frontends/visual/visual_slam.h). Joined at the next keyframe instead
// (ORB-SLAM), the frames between were tracked against the map before the
// BA: on the KITTI 06 excerpt the end-point error went from 0.67 to 0.85 %
// at half resolution and on the TUM RGB-D excerpt from 7.2 to 11.0 %.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_ODOMETRY_H_
#define SLAM_FRONTENDS_STEREO_STEREO_ODOMETRY_H_

#include <cstdint>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "core/graph.h"
#include "core/trajectory.h"
#include "frontends/stereo/stereo_frame.h"

namespace slam {

struct StereoOdometryConfig {
  // Measurement noise and the outlier tests.
  // Keypoint noise at octave 0, times scale_factor^octave: FAST corners sit
  // on whole pixels (0.29 px from rounding alone) and move by about as
  // much between views; the whitened residuals of the KITTI excerpt have an
  // RMS near 0.3 px.
  double pixel_sigma = 0.5;
  // Disparity noise, pixels at every octave: the disparity is refined on
  // full-resolution patches (stereo_features.h step 3), whatever the
  // octave of the keypoint, and u_R = u_L - d shares u_L's error
  // (StereoInformation). Depth noise is then disparity_sigma z^2 / (fx b),
  // growing with the square of the depth. Chosen on the KITTI 06 excerpt
  // at half resolution (README).
  double disparity_sigma = 0.5;
  double scale_factor = 1.2;   // Of the feature pyramid.
  double chi2_stereo = 7.815;  // 95 % of chi2 with 3 dof.
  double chi2_mono = 5.991;    // 95 % of chi2 with 2 dof.
  // Close and far points (step 4): ORB-SLAM2's 40 baselines.
  double close_depth_baselines = 40.0;
  int far_point_min_keyframes = 3;
  double min_parallax = 0.02;  // rad (ORB-SLAM: cos 0.9998, 1.1 deg).
  bool far_points_wait = false;
  // Tracking.
  int local_map_keyframes = 10;
  double search_radius = 15.0;  // Pixels at octave 0.
  int max_descriptor_distance = 80;
  double match_ratio = 0.9;
  int pose_rounds = 4;
  int pose_iterations = 10;  // Per round.
  int min_inliers = 15;
  // Step 4 with the matched points free as well, held by their keyframe
  // observations (those keyframes fixed; copies, the map is not changed):
  // a point only one keyframe has seen has its depth from one stereo pair,
  // wrong by pixels once projected a few frames later; held exact, it
  // failed the chi2 test and the frames between keyframes kept 30-40 % of
  // the matches. A match is an inlier only if its point still agrees with
  // those keyframes. Off: it halves the one-frame error of the frames
  // between keyframes on the synthetic world, but on the KITTI 06 excerpt
  // it made the RPE worse (0.025 -> 0.052 m full, 0.052 -> 0.086 m half).
  bool refine_with_structure = false;
  // Steps 2 and 7 (the last frame's points; the tracking chain as a
  // factor between keyframes).
  bool track_last_frame = true;
  bool keyframe_odometry = true;
  // PnP-RANSAC fallback.
  double pnp_reprojection_error = 3.0;  // Pixels.
  int pnp_iterations = 300;
  double pnp_ratio = 0.8;  // Brute-force matching ratio test.
  // Keyframes (step 6).
  double keyframe_tracked_ratio = 0.75;  // ORB-SLAM2 (stereo).
  int keyframe_close_tracked = 20;       // ORB-SLAM2: 100 (and 70 new).
  int keyframe_new_close = 70;
  double keyframe_rotation = 0.17;  // rad (about 10 deg).
  int keyframe_min_frames = 2;
  int keyframe_max_frames = 10;
  // Output poses of the frames between two keyframes (see "Every frame
  // keeps its pose" above): false, each frame's own tracking, with the
  // bundle adjustment's change of the two keyframes spread along them;
  // true, the same rotation, but the position at the frame's share of the
  // frames on the way between the two bundle-adjusted keyframes
  // (ScrewInterpolation: constant velocity between keyframes); its own
  // tracked position is used only inside (prediction, keyframe odometry).
  // A frame's position is tracked from one frame's matches to the few
  // close points, held against a map it does not refine; a keyframe's
  // pose is bundle adjusted: on the KITTI 06 excerpt at half resolution two
  // keyframes 2 frames apart are 0.027 m off their true relative position,
  // the two frames around a keyframe 0.039 m (README). Frames after the
  // last keyframe keep their tracking.
  bool interpolate_between_keyframes = false;
  // Between the two (used when interpolate_between_keyframes is false): the
  // positions of the frames between two keyframes smoothed (a fixed-interval
  // smoother, step 10). Each frame's tracked position is a measurement with
  // the covariance of its tracking (the pose-only refinement's Hessian over
  // its matches, the points held exact); the prior is that the frames
  // follow the screw path between the two keyframes (constant velocity in
  // the moving frame) up to an acceleration: the deviation's second
  // difference over consecutive frames, divided by their time steps, is
  // N(0, between_acceleration_sigma^2) per axis (m/s^2). Where the tracking
  // is precise or the motion changes, the measurements win; where the
  // tracking is poor and the motion steady, the keyframes' path does. The
  // rotation stays as tracked. 0: off.
  double between_acceleration_sigma = 2.0;
  // Stereo points to start the map; frames before it stay at the origin
  // and count as lost.
  int min_initial_points = 50;
  // Map point culling.
  int min_point_observations = 2;
  int cull_after_keyframes = 2;
  // Bundle adjustment.
  int window_keyframes = 8;
  int local_ba_iterations = 10;
  int final_ba_iterations = 30;       // 0: no final global BA.
  bool local_mapping_thread = false;  // Step 8 on a second thread (above).
};

bool ValidateStereoOdometryConfig(const StereoOdometryConfig& config,
                                  std::string* error);

// The information matrix of a stereo measurement (u_L, u_R, v)
// (factors/stereo_projection.h) whose keypoint (u_L, v) has noise
// pixel_sigma on each axis and whose disparity d = u_L - u_R has
// disparity_sigma, independent of it: u_R shares u_L's error.
Eigen::Matrix3d StereoInformation(double pixel_sigma, double disparity_sigma);

// The pose at the share s (in [0, 1]) of the way from the identity to p
// along SE(3)'s geodesic, Exp(s Log(p)): constant velocity in the moving
// frame, a circular arc for a constant turn rate (a chord would cut a
// 10 deg turn over 2.4 m by 5 cm at its middle).
Pose3 ScrewInterpolation(const Pose3& p, double s);

// What happened to one frame.
struct StereoFrameResult {
  int64_t index = 0;
  int matches = 0;  // Matches before the pose refinement.
  int inliers = 0;  // After.
  bool used_pnp = false;
  bool lost = false;
  bool initialized = false;  // The map exists after this frame.
  bool keyframe = false;
  int new_points = 0;
  int close_tracked = 0;  // Inliers at close stereo keypoints.
  double tracking_ms = 0.0;
  double local_ba_ms = 0.0;
};

struct StereoOdometryStats {
  int frames = 0;
  int keyframes = 0;
  int pnp_fallbacks = 0;
  int lost_frames = 0;
  int points_created = 0;
  int observations_removed = 0;
  int points_culled = 0;
  int local_bundle_adjustments = 0;
  double final_ba_ms = 0.0;
  // Robust chi2 (sum of rho(e^T Omega e), Huber) of the global BA.
  double global_ba_initial_chi2 = 0.0;
  double global_ba_final_chi2 = 0.0;
};

class StereoOdometry {
 public:
  StereoOdometry(const StereoOdometryConfig& config,
                 const StereoCalibration& calibration, int image_width,
                 int image_height);
  StereoOdometry(StereoOdometry&&) noexcept;
  ~StereoOdometry();  // Waits for a local BA on its thread.

  StereoFrameResult AddFrame(const StereoFeatureFrame& frame);
  // The global bundle adjustment (step 9).
  void Finish();
  // Merges the local BA running on its thread (local_mapping_thread), if any:
  // call before reading or changing the map other than by AddFrame.
  void WaitForLocalMapping();

  // Every frame's camera pose (T_world_camera, the first frame at the
  // origin), stamped, in frame order.
  Trajectory FrameTrajectory() const;
  // Keyframes and points with their observations.
  const Graph& graph() const { return graph_; }
  std::vector<Eigen::Vector3d> MapPoints() const;
  // Each live map point's graph id and its observations: the frame index
  // of the observing keyframe, the keypoint index in that frame, and
  // whether it is a stereo (else monocular) factor.
  struct TrackObservation {
    int64_t frame = 0;
    int keypoint = 0;
    bool stereo = false;
  };
  struct PointTrack {
    int64_t point = 0;
    std::vector<TrackObservation> observations;
  };
  std::vector<PointTrack> PointTracks() const;
  // The graph for computations that need write access (marginals).
  Graph* mutable_graph() { return &graph_; }

  // Keyframes, for loop closing (stereo_loop_closing.h).
  size_t NumKeyframes() const { return keyframes_.size(); }
  Pose3 KeyframePose(int64_t keyframe) const;
  const StereoFeatureFrame& KeyframeFeatures(int64_t keyframe) const {
    return keyframes_[keyframe].features;
  }
  // Moves every keyframe to `poses` (one per keyframe) and every map point
  // with the keyframe that created it (rigidly), so that the map follows a
  // pose-graph correction.
  void MoveKeyframes(const std::vector<Pose3>& poses);
  // Adds a relative-pose constraint between two keyframes (a loop closure:
  // measurement of T_candidate^-1 T_query, information over the between
  // factor's error, factors/between_se3.h) with a robust kernel; the final
  // global bundle adjustment (Finish) includes it. -1 if invalid.
  FactorId AddKeyframeConstraint(int64_t candidate, int64_t query,
                                 const Pose3& measurement,
                                 const Eigen::Matrix<double, 6, 6>& information,
                                 std::shared_ptr<ceres::LossFunction> loss);
  const StereoOdometryStats& stats() const { return stats_; }

 private:
  struct Observation {
    int64_t keyframe;
    int keypoint;
    FactorId factor;
  };
  struct MapPoint {
    cv::Mat descriptor;  // 1 x 32, from the latest keyframe observing it.
    std::vector<Observation> observations;
    int64_t local_stamp = -1;     // Frame that last put it into a local map.
    int64_t anchor_keyframe = 0;  // The keyframe that created it.
    // Its depth is known: from a close stereo observation, or triangulated
    // by far_point_min_keyframes keyframes (step 4).
    bool confirmed = false;
  };
  struct Keyframe {
    int64_t frame_index = 0;
    TimeNs stamp = 0;
    StereoFeatureFrame features;
    std::vector<int64_t> point_of_keypoint;  // -1: none.
    std::vector<int64_t> created_points;
    // The tracking from the previous keyframe (keyframe_odometry).
    bool has_chain = false;
    Pose3 chain_from_previous;
  };
  struct FrameRecord {
    int64_t index = 0;
    TimeNs stamp = 0;
    int64_t keyframe = -1;  // Reference keyframe; -1: before the map.
    Pose3 keyframe_to_frame;
    // Covariance of the tracked position, camera frame (right
    // perturbation); zero when unknown (keyframes, lost frames).
    Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Zero();
  };
  struct Match {
    int keypoint;
    int64_t point;
    int distance;
  };

  // A stereo keypoint of the last frame (when it is not a keyframe) that
  // no map point explains: a point for the next frame's tracking only.
  struct LastFramePoint {
    Eigen::Vector3d position;  // World frame.
    cv::Mat descriptor;        // 1 x 32 (a row of the frame's).
  };
  // Match::point of a last-frame point: -2 - its index (-1 means none).
  static bool IsLastFramePoint(int64_t point) { return point <= -2; }
  static int64_t LastFramePointId(size_t index) {
    return -2 - static_cast<int64_t>(index);
  }
  static size_t LastFramePointIndex(int64_t point) {
    return static_cast<size_t>(-2 - point);
  }
  // A map point or a last-frame point.
  Eigen::Vector3d Position(int64_t point) const;
  const cv::Mat& Descriptor(int64_t point) const;
  void UpdateLastFramePoints(const StereoFeatureFrame& frame, const Pose3& pose,
                             const std::vector<Match>& matches, bool keyframe);
  // Keypoint i (with stereo) in its camera's frame.
  Eigen::Vector3d StereoPoint(const StereoFeatureFrame& frame, size_t i) const;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  // The pose information (over the SE(3) manifold's tangent) of the
  // frame's matches at `pose`, the points held; only the last frame's
  // points' with last_frame_only.
  void TrackingInformation(const StereoFeatureFrame& frame,
                           const std::vector<Match>& matches, const Pose3& pose,
                           bool last_frame_only, Matrix6* information) const;
  // Extends the tracking chain from the last keyframe by this frame.
  void ChainTracking(const StereoFeatureFrame& frame,
                     const std::vector<Match>& matches, const Pose3& previous,
                     const Pose3& pose, bool after_keyframe);
  // The chain as a relative-pose factor from keyframe id - 1 to id.
  void AddKeyframeOdometry(int64_t id);
  Pose3 FramePose(const FrameRecord& record) const;
  // Step 10: the positions of the frames [first, last) of frames_, all
  // between keyframe a and a + 1, smoothed (between_acceleration_sigma);
  // `poses` holds their FramePose and is updated in place.
  void SmoothBetweenKeyframes(size_t first, size_t last,
                              std::vector<Pose3>* poses) const;
  Eigen::Vector3d PointValue(int64_t point) const;
  std::vector<int64_t> LocalMapPoints(int64_t frame_index);
  std::vector<Match> SearchByProjection(const StereoFeatureFrame& frame,
                                        const Pose3& pose,
                                        const std::vector<int64_t>& points,
                                        double radius) const;
  std::vector<Match> SearchByDescriptor(
      const StereoFeatureFrame& frame,
      const std::vector<int64_t>& points) const;
  bool PnpRansac(const StereoFeatureFrame& frame,
                 const std::vector<Match>& matches, Pose3* pose) const;
  // Step 4; returns the number of inliers and keeps only them in *matches.
  int OptimizePose(const StereoFeatureFrame& frame, std::vector<Match>* matches,
                   Pose3* pose) const;
  // A stereo factor for a stereo keypoint, else a monocular one.
  bool MakeObservationFactor(const StereoFeatureFrame& frame, int keypoint,
                             const Key& camera, const Key& point,
                             Factor* factor) const;
  double Chi2Threshold(const Factor& factor) const;
  // A stereo keypoint within close_depth_baselines.
  bool IsClose(const StereoFeatureFrame& frame, size_t keypoint) const;
  int64_t AddKeyframe(const StereoFeatureFrame& frame, const Pose3& pose,
                      const std::vector<Match>& matches, int* new_points);
  // Step 8: solved at once, or started on its thread (local_mapping_thread).
  void LocalBundleAdjustment(int64_t newest_keyframe);
  struct LocalBaJob;
  // After the solve: the outlier observations removed, points culled.
  void CompleteLocalBundleAdjustment(const LocalBaJob& job);
  // The job's values written back to the graph, then the above.
  void MergeLocalBundleAdjustment(const LocalBaJob& job);
  void RemoveOutlierObservations(const std::vector<int64_t>& points);
  void RemoveObservation(int64_t point, size_t observation);
  // Removes the point if fewer than min_point_observations keyframes see
  // it; true if it was removed.
  bool CullPoint(int64_t point);

  StereoOdometryConfig config_;
  StereoCalibration calibration_;
  PinholeCalibration pinhole_;
  int width_;
  int height_;
  Graph graph_;
  std::vector<Keyframe> keyframes_;  // Index = keyframe id.
  std::vector<MapPoint> points_;     // Index = point id (may be removed).
  std::vector<bool> point_alive_;
  // Point nodes left without observations, removed from the graph in one
  // pass (RemoveDeadPoints) rather than one scan of the factors each.
  std::vector<Key> dead_points_;
  void RemoveDeadPoints();
  std::vector<FrameRecord> frames_;
  Pose3 last_motion_;  // T_prev^-1 T_current.
  std::vector<LastFramePoint> last_frame_points_;
  // The tracking from the last keyframe to the current frame: relative
  // pose and its covariance (tangent of the right perturbation).
  bool chain_valid_ = false;
  Pose3 chain_;
  Matrix6 chain_covariance_ = Matrix6::Zero();
  std::vector<FactorId> odometry_factor_;  // Per keyframe; -1: none.
  int frames_since_keyframe_ = 0;
  StereoOdometryStats stats_;
  // The local BA on its thread (local_mapping_thread); the job outlives the
  // future, which waits for the thread when destroyed.
  std::unique_ptr<LocalBaJob> local_ba_job_;
  std::future<void> local_ba_done_;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_ODOMETRY_H_
