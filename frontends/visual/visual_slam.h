// Visual SLAM over a sequence of frames, one pipeline for every camera that
// gives keypoints with depth (a rectified stereo pair, an RGB-D camera;
// frame_source.h), as ORB-SLAM2 serves both from one system:
//
//  1. Frames: the source decodes frame k + 1 on a worker thread while frame
//     k is worked on, and extracts each frame's features (keypoints,
//     descriptors, right-image u coordinates; VisualFrameSource).
//  2. Tracking, keyframes, map points and local bundle adjustment, frame by
//     frame (StereoOdometry::AddFrame, frontends/stereo/stereo_odometry.h,
//     its steps 1-8).
//  3. Vocabulary (loop_closure.enabled): loops.vocabulary when given, else
//     one trained on the keyframes' own descriptors (TrainVocabulary,
//     place_recognition.h; no download needed).
//  4. Loop closing over the keyframes: place recognition, verification,
//     pose graph, the map corrected (CloseStereoLoops,
//     frontends/stereo/stereo_loop_closing.h).
//  5. Global bundle adjustment over every keyframe and point, the loops
//     included (StereoOdometry::Finish, step 9).
//  6. Results: every frame's camera pose, the map points, the per-frame
//     timings by stage and the statistics (VisualSlamResult); the graph with
//     its observations stays available (odometry()). A source with a
//     fixed-rate capture clock under arrival stamps (FixedRateCapture: RGB-D)
//     gets its poses, estimated at the capture instants, moved to the
//     stamps (capture_clock.h); the graph keeps the stamps as they are.
//
// Nothing here reads files but the vocabulary (step 3) or writes any: the
// caller (apps/visual/) reads flags and configs, reports and writes.
#ifndef SLAM_FRONTENDS_VISUAL_VISUAL_SLAM_H_
#define SLAM_FRONTENDS_VISUAL_VISUAL_SLAM_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/trajectory.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_loop_closing.h"
#include "frontends/stereo/stereo_odometry.h"
#include "frontends/visual/frame_source.h"
#include "frontends/visual/place_recognition.h"

namespace slam {

struct VisualSlamConfig {
  StereoOdometryConfig odometry;         // Steps 2 and 5.
  StereoLoopClosingConfig loop_closure;  // Steps 3 and 4 (enabled).
  // Place recognition (steps 3-4). The verification is always PnP on the
  // keyframes' points (CloseStereoLoops); orb_features is not used (the
  // keyframes' own features are).
  LoopsConfig loops;
};

// One frame's work, milliseconds.
struct VisualFrameTiming {
  int64_t frame = 0;
  StereoFeatureTimings features;  // Detection; right coordinates.
  double read_ms = 0.0;           // Waiting for the decoded images.
  double tracking_ms = 0.0;
  double local_ba_ms = 0.0;
  double total_ms = 0.0;  // Features + matching + tracking + local BA.
  bool keyframe = false;
  int inliers = 0;
};

struct VisualSlamResult {
  Trajectory trajectory;  // Every frame's camera pose, the first at origin.
  std::vector<Eigen::Vector3d> map_points;  // World frame.
  std::vector<VisualFrameTiming> timings;   // One per frame.
  StereoOdometryStats stats;
  // Steps 3-4.
  std::string vocabulary_source;  // The file, or "trained on the keyframes".
  double vocabulary_seconds = 0.0;
  double loop_seconds = 0.0;  // Vocabulary and loop closing.
  StereoLoopClosingResult loops;
};

// Progress of a run: the fraction of frames done after each frame (step 2),
// and lines of text (the vocabulary, each loop, the loop closing summary).
struct VisualSlamCallbacks {
  std::function<void(double fraction)> progress;
  std::function<void(const std::string& line)> log;
};

class VisualSlam {
 public:
  // The source fixes the camera and the image size.
  VisualSlam(const VisualSlamConfig& config, const VisualFrameSource* source);

  // Steps 1-6 over every frame of the source. False with the error of a
  // vocabulary that cannot be read (before any frame), a frame that cannot
  // be decoded, first frames of which none starts the map (after 50 frames,
  // or all when fewer: nothing can be tracked), a vocabulary that cannot be
  // trained, or the loop closing (nothing of the run is then meaningful).
  bool Run(const VisualSlamCallbacks& callbacks, VisualSlamResult* result,
           std::string* error);

  // Keyframes, map points and their observations (after Run).
  const StereoOdometry& odometry() const { return *odometry_; }

 private:
  // With `vocabulary` loaded (loops.vocabulary) or to be trained.
  bool CloseLoops(const VisualSlamCallbacks& callbacks,
                  bow::Vocabulary* vocabulary, VisualSlamResult* result,
                  std::string* error);

  VisualSlamConfig config_;
  const VisualFrameSource* source_;
  std::unique_ptr<StereoOdometry> odometry_;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_VISUAL_VISUAL_SLAM_H_
