#include "frontends/visual/visual_slam.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <future>
#include <sstream>
#include <utility>
#include <vector>

#include "frontends/visual/capture_clock.h"

namespace slam {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A run fails when none of its first frames (this many, or all when fewer)
// could start the map: nothing can be tracked (blank, uniform or noise
// images, or a calibration that does not fit them), so there is no point
// in decoding the rest (the user is told at once, not after the last frame).
constexpr size_t kFramesToStartTheMap = 50;

}  // namespace

VisualSlam::VisualSlam(const VisualSlamConfig& config,
                       const VisualFrameSource* source)
    : config_(config),
      source_(source),
      odometry_(std::make_unique<StereoOdometry>(
          config.odometry, source->calibration(), source->width(),
          source->height())) {}

bool VisualSlam::Run(const VisualSlamCallbacks& callbacks,
                     VisualSlamResult* result, std::string* error) {
  *result = VisualSlamResult();
  const size_t frames = source_->NumFrames();
  // Inputs first: a vocabulary file is read before any frame (a missing
  // one used to be found after the last frame).
  bow::Vocabulary vocabulary;
  if (config_.loop_closure.enabled && !config_.loops.vocabulary.empty()) {
    const auto start = Clock::now();
    if (!vocabulary.Load(config_.loops.vocabulary, error)) return false;
    result->vocabulary_seconds = SecondsSince(start);
  }
  // Steps 1-2. Decoding the next frame overlaps with the work on this one.
  {
    VisualImages images, next_images;
    std::string next_error;
    std::future<bool> next;
    auto load = [&](size_t k) {
      return source_->Load(k, &next_images, &next_error);
    };
    for (size_t k = 0; k < frames; ++k) {
      VisualFrameTiming t;
      t.frame = static_cast<int64_t>(k);
      const auto read_start = Clock::now();
      const bool loaded =
          k == 0 ? source_->Load(0, &images, error) : next.get();
      if (!loaded) {
        if (k > 0) *error = next_error;
        return false;
      }
      if (k > 0) images = std::move(next_images);
      t.read_ms =
          std::chrono::duration<double, std::milli>(Clock::now() - read_start)
              .count();
      if (k + 1 < frames) next = std::async(std::launch::async, load, k + 1);
      const StereoFeatureFrame features = source_->Extract(images, &t.features);
      const StereoFrameResult r = odometry_->AddFrame(features);
      t.tracking_ms = r.tracking_ms;
      t.local_ba_ms = r.local_ba_ms;
      t.keyframe = r.keyframe;
      t.inliers = r.inliers;
      t.total_ms = t.features.features_ms + t.features.matching_ms +
                   t.tracking_ms + t.local_ba_ms;
      result->timings.push_back(t);
      if (callbacks.progress) {
        callbacks.progress(static_cast<double>(k + 1) / frames);
      }
      if (odometry_->NumKeyframes() == 0 &&
          k + 1 == std::min(frames, kFramesToStartTheMap)) {
        *error = "frames 0-" + std::to_string(k) + ": none has the " +
                 std::to_string(config_.odometry.min_initial_points) +
                 " points with depth needed to start the map (blank, "
                 "uniform or noise images, or a calibration that does not "
                 "fit them): nothing can be tracked";
        return false;
      }
    }
  }
  // The last keyframe's local BA, when on its thread, in the map first.
  odometry_->WaitForLocalMapping();
  // Steps 3-4.
  if (config_.loop_closure.enabled &&
      !CloseLoops(callbacks, &vocabulary, result, error)) {
    return false;
  }
  // Steps 5-6.
  odometry_->Finish();
  result->trajectory = odometry_->FrameTrajectory();
  if (source_->FixedRateCapture()) {
    std::vector<TimeNs> stamps;
    for (const StampedPose& p : result->trajectory) stamps.push_back(p.stamp);
    const CaptureClock clock = FitCaptureClock(stamps);
    char line[256];
    if (clock.fixed_rate) {
      result->trajectory = PosesAtStamps(result->trajectory, clock.capture);
      std::snprintf(line, sizeof(line),
                    "capture clock %.3f ms (%.2f Hz) fitted to the stamps, "
                    "jitter %.2f ms rms, latency up to %.2f ms: poses of the "
                    "capture instants, written at the stamps",
                    1e3 * clock.period, 1.0 / clock.period,
                    1e3 * clock.jitter_rms, 1e3 * clock.latency_max);
    } else {
      std::snprintf(line, sizeof(line),
                    "the stamps fit no fixed frame rate: poses written as "
                    "those of the stamps");
    }
    if (callbacks.log) callbacks.log(line);
  }
  result->map_points = odometry_->MapPoints();
  result->stats = odometry_->stats();
  return true;
}

bool VisualSlam::CloseLoops(const VisualSlamCallbacks& callbacks,
                            bow::Vocabulary* loaded, VisualSlamResult* result,
                            std::string* error) {
  const auto loop_start = Clock::now();
  const double load_seconds = result->vocabulary_seconds;  // Read in Run.
  const LoopsConfig& loops = config_.loops;
  // Too few keyframes for any query to have a candidate (the keyframes
  // just before a query never are): no vocabulary to train, no detection;
  // the outcome is the same as theirs, no loop. A short run's whole time
  // counts (20 KITTI frames, 10 keyframes: training was a sixth of it).
  const size_t needed =
      static_cast<size_t>(bow::MinKeyframesForALoop(loops.detector));
  if (odometry_->NumKeyframes() < needed) {
    result->loop_seconds = SecondsSince(loop_start) + load_seconds;
    if (callbacks.log) {
      char line[256];
      std::snprintf(line, sizeof(line),
                    "loop closure: none possible among %zu keyframes (a "
                    "query's candidates are more than exclude_recent = %d "
                    "keyframes back: %zu needed); not run",
                    odometry_->NumKeyframes(), loops.detector.exclude_recent,
                    needed);
      callbacks.log(line);
    }
    return true;
  }
  bow::Vocabulary& vocabulary = *loaded;
  result->vocabulary_source = loops.vocabulary;
  if (loops.vocabulary.empty()) {
    std::vector<cv::Mat> descriptors;
    size_t count = 0;
    for (size_t k = 0; k < odometry_->NumKeyframes(); ++k) {
      descriptors.push_back(odometry_->KeyframeFeatures(k).descriptors);
      count += descriptors.back().rows;
    }
    if (!TrainVocabulary(loops, descriptors, count, &vocabulary, error)) {
      *error = "vocabulary: " + *error;
      return false;
    }
    result->vocabulary_source = "trained on the keyframes";
  }
  result->vocabulary_seconds += SecondsSince(loop_start);
  char line[512];
  std::snprintf(
      line, sizeof(line), "vocabulary %s: k = %d, L = %d, %zu words (%.2f s)",
      result->vocabulary_source.c_str(), vocabulary.k(), vocabulary.levels(),
      vocabulary.size(), result->vocabulary_seconds);
  if (callbacks.log) callbacks.log(line);
  std::ostringstream loop_log;
  if (!CloseStereoLoops(vocabulary, loops.detector, config_.loop_closure,
                        source_->calibration(), odometry_.get(), &result->loops,
                        &loop_log, error)) {
    *error = "loop closing: " + *error;
    return false;
  }
  result->loop_seconds = SecondsSince(loop_start) + load_seconds;
  if (callbacks.log) {
    std::istringstream lines(loop_log.str());
    for (std::string text; std::getline(lines, text);) callbacks.log(text);
    const StereoLoopClosingResult& l = result->loops;
    std::snprintf(line, sizeof(line),
                  "loop closure: %d candidates verified or rejected, %d "
                  "accepted, %d rejected, largest keyframe correction %.3f m "
                  "(%.2f s)",
                  l.detected, l.accepted, l.rejected, l.largest_correction,
                  result->loop_seconds);
    callbacks.log(line);
  }
  return true;
}

}  // namespace slam
