// slam run with run.pipeline: stereo (stereo visual odometry on a
// KITTI-style sequence folder, frontends/stereo/stereo_odometry.h).
//
//   slam run --config configs/kitti_stereo.yaml [--datasets DIR]
//            [--output_dir DIR] [--gt POSES.txt] [--report FILE.json]
//
// Outputs in output_dir, all written only after every frame was processed
// (nothing is left behind by a run that fails):
//   trajectory_kitti.txt  every frame's left-camera pose, KITTI format
//   trajectory.tum        the same with stamps (times.txt or frame_period)
//   graph.g2o             keyframes, map points and their stereo / pinhole
//                         observations (slam optimize reads it back)
//   map_points.ply        the map points (ASCII PLY)
//   map.png               map points and trajectory seen from above
//   timings.csv           per-frame milliseconds by stage
//   plots/                with ground truth: the plots of slam eval --plot
#include <gflags/gflags.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/json.h"
#include "apps/map_plot.h"
#include "apps/progress_bar.h"
#include "apps/run_config.h"
#include "apps/visual/stereo_run_config.h"
#include "apps/visual/visual_commands.h"
#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/kitti_sequence_io.h"
#include "datasets/text_util.h"
#include "datasets/trajectory_io.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_images.h"
#include "frontends/stereo/stereo_loop_closing.h"
#include "frontends/stereo/stereo_odometry.h"

DECLARE_string(output_dir);

namespace slam {
namespace {

namespace fs = std::filesystem;

struct FrameTiming {
  int64_t frame = 0;
  StereoFeatureTimings features;
  double read_ms = 0.0;
  double tracking_ms = 0.0;
  double local_ba_ms = 0.0;
  double total_ms = 0.0;  // Features + matching + tracking + local BA.
  bool keyframe = false;
  int inliers = 0;
};

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double pos = p * (values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (pos - lo) * (values[hi] - values[lo]);
}

std::string PlyText(const std::vector<Eigen::Vector3d>& points) {
  std::string out =
      "ply\nformat ascii 1.0\ncomment slam stereo map points (world frame = "
      "first left camera, x right, y down, z forward)\nelement vertex " +
      std::to_string(points.size()) +
      "\nproperty double x\nproperty double y\nproperty double z\n"
      "end_header\n";
  for (const Eigen::Vector3d& p : points) {
    text::AppendDouble(p.x(), &out);
    out += ' ';
    text::AppendDouble(p.y(), &out);
    out += ' ';
    text::AppendDouble(p.z(), &out);
    out += '\n';
  }
  return out;
}

std::string TimingsCsv(const std::vector<FrameTiming>& timings) {
  std::string out =
      "# frame, read_ms, features_ms, matching_ms, tracking_ms, local_ba_ms, "
      "total_ms, keyframe, inliers\n";
  char line[256];
  for (const FrameTiming& t : timings) {
    std::snprintf(line, sizeof(line),
                  "%lld,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d\n",
                  static_cast<long long>(t.frame), t.read_ms,
                  t.features.features_ms, t.features.matching_ms, t.tracking_ms,
                  t.local_ba_ms, t.total_ms, t.keyframe ? 1 : 0, t.inliers);
    out += line;
  }
  return out;
}

JsonObject StageJson(const std::vector<double>& ms) {
  JsonObject o;
  o.Add("median_ms", Percentile(ms, 0.5)).Add("p95_ms", Percentile(ms, 0.95));
  return o;
}

// Map points and the camera path seen from above: the world is the first
// left camera's frame (x right, y down, z forward), so the ground plane is
// x-z (a plot chosen by extent could pick the vertical axis on a straight
// drive).
MapPlotData TopView(const Trajectory& trajectory,
                    const std::vector<Eigen::Vector3d>& points) {
  MapPlotData data;
  data.title = "map points and camera path seen from above (x-z plane)";
  data.xlabel = "x [m] (right of the first camera)";
  data.ylabel = "z [m] (ahead of the first camera)";
  for (const StampedPose& p : trajectory) {
    data.trajectory_x.push_back(p.pose.t.x());
    data.trajectory_y.push_back(p.pose.t.z());
  }
  for (const Eigen::Vector3d& p : points) {
    data.landmark_x.push_back(p.x());
    data.landmark_y.push_back(p.z());
  }
  return data;
}

int RunStereo(const StereoRunConfig& config) {
  std::string error;
  const auto start = std::chrono::steady_clock::now();
  const std::string dir = ResolveDatasetPath(config.sequence);
  KittiSequenceOptions options;
  options.default_frame_period = config.frame_period;
  KittiSequence sequence;
  if (!ReadKittiSequence(dir, options, &sequence, &error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  size_t available = sequence.left_images.size();
  if (config.max_frames > 0) {
    available = std::min(available, static_cast<size_t>(config.max_frames));
  }
  // The images in playback order (forward, or forward then back).
  std::vector<size_t> order;
  for (size_t k = 0; k < available; ++k) order.push_back(k);
  if (config.playback == "forward_backward") {
    for (size_t k = available - 1; k-- > 0;) order.push_back(k);
  }
  const size_t frames = order.size();
  const StereoCalibration& calibration = sequence.calibration;
  std::printf(
      "run: stereo %s: %zu frames (%s), fx %.4f fy %.4f cx %.4f cy %.4f, "
      "baseline "
      "%.6f m, %s\n",
      dir.c_str(), frames, config.playback.c_str(), calibration.fx,
      calibration.fy, calibration.cx, calibration.cy, calibration.baseline,
      sequence.has_times ? "stamps from times.txt"
                         : ("no times.txt: frames " +
                            std::to_string(config.frame_period) + " s apart")
                               .c_str());

  // Ground truth: read (and checked) before the work.
  std::string gt_path = FLAGS_gt.empty() ? config.ground_truth : FLAGS_gt;
  if (FLAGS_gt.empty() && !gt_path.empty())
    gt_path = ResolveDatasetPath(gt_path);
  if (gt_path.empty()) gt_path = sequence.ground_truth_path;
  TrajectoryData gt;
  if (!gt_path.empty()) {
    TrajectoryReadOptions read;
    read.format = TrajectoryFormat::kKitti;
    if (!ReadTrajectory(gt_path, read, &gt, &error)) {
      std::cerr << "run: " << error << "\n";
      return 1;
    }
    if (gt.poses.size() < available) {
      std::cerr << "run: " << gt_path << ": " << gt.poses.size()
                << " poses for " << available << " frames\n";
      return 1;
    }
    Trajectory played;
    for (size_t k : order) played.push_back(gt.poses[k]);
    gt.poses = std::move(played);
  }
  EvalSettings eval_settings;
  eval_settings.align = AlignmentMethod::kNone;
  eval_settings.kitti = true;
  if (!LoadEvalSectionOfConfig(FLAGS_config, &eval_settings, &error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  eval_settings.association = ChooseAssociation(false, false);

  // The first pair fixes the image size (checked against the calibration).
  StereoImages images;
  if (!LoadStereoImages(sequence, 0, 0, 0, &images, &error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  const int width = images.left.cols, height = images.left.rows;
  // Frames are numbered and stamped in playback order: the sequence's stamps
  // forward, frame_period apart when played forward and back.
  auto stamp_of = [&](size_t k) {
    return config.playback == "forward" ? sequence.stamps[k]
                                        : SecondsToNs(config.frame_period * k);
  };
  images.stamp = stamp_of(0);
  std::error_code ec;
  fs::create_directories(config.output_dir, ec);
  if (ec) {
    std::cerr << "run: " << config.output_dir
              << ": cannot create directory: " << ec.message() << "\n";
    return 1;
  }

  StereoFeatureExtractor extractor(config.features, calibration);
  StereoOdometry odometry(config.odometry, calibration, width, height);
  std::vector<FrameTiming> timings;
  {
    ProgressBar bar("processing");
    // Decoding the next pair overlaps with the work on the current one.
    std::future<bool> next;
    StereoImages next_images;
    std::string next_error;
    auto load = [&](size_t k) {
      if (!LoadStereoImages(sequence, order[k], width, height, &next_images,
                            &next_error)) {
        return false;
      }
      next_images.index = static_cast<int64_t>(k);
      next_images.stamp = stamp_of(k);
      return true;
    };
    for (size_t k = 0; k < frames; ++k) {
      FrameTiming t;
      t.frame = static_cast<int64_t>(k);
      const auto read_start = std::chrono::steady_clock::now();
      if (k > 0) {
        if (!next.get()) {
          std::cerr << "\nrun: " << next_error << "\n";
          return 1;
        }
        images = std::move(next_images);
      }
      t.read_ms = std::chrono::duration<double, std::milli>(
                      std::chrono::steady_clock::now() - read_start)
                      .count();
      if (k + 1 < frames) next = std::async(std::launch::async, load, k + 1);
      const StereoFeatureFrame features =
          extractor.Extract(images, &t.features);
      const StereoFrameResult r = odometry.AddFrame(features);
      t.tracking_ms = r.tracking_ms;
      t.local_ba_ms = r.local_ba_ms;
      t.keyframe = r.keyframe;
      t.inliers = r.inliers;
      t.total_ms = t.features.features_ms + t.features.matching_ms +
                   t.tracking_ms + t.local_ba_ms;
      timings.push_back(t);
      bar.Update(static_cast<double>(k + 1) / frames);
    }
  }
  // Loop closing over the keyframes, then the global bundle adjustment.
  StereoLoopClosingResult loops;
  double vocabulary_seconds = 0.0, loop_seconds = 0.0;
  if (config.loop_closure.enabled) {
    const auto loop_start = std::chrono::steady_clock::now();
    bow::Vocabulary vocabulary;
    std::string source = config.loops.vocabulary;
    if (!config.loops.vocabulary.empty()) {
      if (!vocabulary.Load(ResolveDatasetPath(config.loops.vocabulary),
                           &error)) {
        std::cerr << "run: " << error << "\n";
        return 1;
      }
    } else {
      // Trained on the keyframes' own descriptors (no download needed).
      std::vector<cv::Mat> descriptors;
      size_t count = 0;
      for (size_t k = 0; k < odometry.NumKeyframes(); ++k) {
        descriptors.push_back(odometry.KeyframeFeatures(k).descriptors);
        count += descriptors.back().rows;
      }
      bow::VocabularyTrainingOptions options;
      options.k = config.loops.vocabulary_k;
      options.max_descriptors = config.loops.vocabulary_max_descriptors;
      options.levels = VocabularyLevelsFor(
          config.loops, options.max_descriptors > 0
                            ? std::min<size_t>(count, options.max_descriptors)
                            : count);
      if (!vocabulary.Train(descriptors, options, &error)) {
        std::cerr << "run: vocabulary: " << error << "\n";
        return 1;
      }
      source = "trained on the keyframes";
    }
    vocabulary_seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - loop_start)
                             .count();
    std::printf("run: vocabulary %s: k = %d, L = %d, %zu words (%.2f s)\n",
                source.c_str(), vocabulary.k(), vocabulary.levels(),
                vocabulary.size(), vocabulary_seconds);
    if (!CloseStereoLoops(vocabulary, config.loops.detector,
                          config.loop_closure, calibration, &odometry, &loops,
                          &std::cout, &error)) {
      std::cerr << "run: loop closing: " << error << "\n";
      return 1;
    }
    loop_seconds = std::chrono::duration<double>(
                       std::chrono::steady_clock::now() - loop_start)
                       .count();
    std::printf(
        "run: loop closure: %d candidates verified or rejected, %d accepted, "
        "%d rejected, largest keyframe correction %.3f m (%.2f s)\n",
        loops.detected, loops.accepted, loops.rejected,
        loops.largest_correction, loop_seconds);
  }
  odometry.Finish();
  const Trajectory trajectory = odometry.FrameTrajectory();
  const StereoOdometryStats& s = odometry.stats();

  // Outputs.
  const fs::path out_dir(config.output_dir);
  const std::string kitti_path = (out_dir / "trajectory_kitti.txt").string();
  const std::string tum_path = (out_dir / "trajectory.tum").string();
  const std::string graph_path = (out_dir / "graph.g2o").string();
  const std::string ply_path = (out_dir / "map_points.ply").string();
  const std::string csv_path = (out_dir / "timings.csv").string();
  const std::string map_path = (out_dir / "map.png").string();
  const std::string plot_dir = (out_dir / "plots").string();
  // A failed run publishes none of what it wrote: main() keeps every output
  // in an OutputStage (datasets/atomic_file.h) until the command succeeds.
  auto fail = [&](const std::string& message) {
    std::cerr << "run: " << message << "\n";
    return 1;
  };
  const std::vector<Eigen::Vector3d> points = odometry.MapPoints();
  if (!WriteTrajectory(kitti_path, trajectory, TrajectoryFormat::kKitti,
                       &error) ||
      !WriteTrajectory(tum_path, trajectory, TrajectoryFormat::kTum, &error) ||
      !WriteG2o(graph_path, odometry.graph(), &error) ||
      !WriteFileAtomically(ply_path, PlyText(points), &error) ||
      !WriteFileAtomically(csv_path, TimingsCsv(timings), &error) ||
      !WriteMapPlot(map_path, TopView(trajectory, points), &error)) {
    return fail(error);
  }

  std::vector<double> total, features, matching, tracking, local_ba;
  for (const FrameTiming& t : timings) {
    total.push_back(t.total_ms);
    features.push_back(t.features.features_ms);
    matching.push_back(t.features.matching_ms);
    tracking.push_back(t.tracking_ms);
    local_ba.push_back(t.local_ba_ms);
  }
  std::printf(
      "run: %d frames, %d keyframes, %zu map points (%d created, %d "
      "observations removed as outliers); %d PnP-RANSAC fallbacks, %d frames "
      "lost; %d local BAs; global BA %.1f ms (robust chi2 %.6g -> %.6g)\n",
      s.frames, s.keyframes, points.size(), s.points_created,
      s.observations_removed, s.pnp_fallbacks, s.lost_frames,
      s.local_bundle_adjustments,
      s.global_ba_initial_chi2 > 0 ? s.final_ba_ms : 0.0,
      s.global_ba_initial_chi2, s.global_ba_final_chi2);
  std::printf("run: per frame (ms)   median     p95\n");
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"features", &features},
      {"stereo matching", &matching},
      {"tracking", &tracking},
      {"local BA", &local_ba},
      {"whole pipeline", &total}};
  for (const auto& [name, values] : stages) {
    std::printf("run:   %-16s %7.2f %7.2f\n", name, Percentile(*values, 0.5),
                Percentile(*values, 0.95));
  }

  JsonObject report;
  report.Add("pipeline", "stereo")
      .Add("sequence", dir)
      .Add("frames", static_cast<int>(trajectory.size()))
      .Add("keyframes", s.keyframes)
      .Add("map_points", points.size())
      .Add("pnp_fallbacks", s.pnp_fallbacks)
      .Add("lost_frames", s.lost_frames);
  JsonObject timing = StageJson(total);
  timing.Add("features", StageJson(features))
      .Add("stereo_matching", StageJson(matching))
      .Add("tracking", StageJson(tracking))
      .Add("local_ba", StageJson(local_ba))
      .Add("global_ba_ms", s.final_ba_ms);
  report.Add("timing", timing);
  JsonObject loop_json;
  loop_json.Add("enabled", config.loop_closure.enabled)
      .Add("candidates", loops.detected)
      .Add("accepted", loops.accepted)
      .Add("rejected", loops.rejected)
      .Add("largest_correction_m", loops.largest_correction)
      .Add("seconds", loop_seconds);
  report.Add("loop_closure", loop_json);

  if (!gt.poses.empty()) {
    EvalResult result;
    EvalLabels labels;
    labels.ref_name = "ground truth";
    labels.est_name = "stereo VO";
    if (!EvaluateAndReport(gt.poses, trajectory, eval_settings, labels,
                           plot_dir, std::cout, &result, &error)) {
      return fail(error);
    }
    JsonObject evaluation = EvalResultJson(result, eval_settings);
    if (!result.ref.empty()) {
      const double end_error =
          (result.est_aligned.back().t - result.ref.back().t).norm();
      const double percent = 100.0 * end_error / result.ref_path_length;
      std::printf("run: end-point error %.4f m over a %.2f m path (%.3f %%)\n",
                  end_error, result.ref_path_length, percent);
      evaluation.Add("end_point_error_m", end_error)
          .Add("end_point_error_percent", percent);
    }
    report.Add("evaluation", evaluation);
  }
  if (!FLAGS_report.empty()) {
    if (!WriteFileAtomically(FLAGS_report, report.ToString(2) + "\n", &error))
      return fail(error);
  }
  std::printf(
      "run: wrote %s, %s, %s, %s, %s, %s%s (%.2f s)\n", kitti_path.c_str(),
      tum_path.c_str(), graph_path.c_str(), ply_path.c_str(), csv_path.c_str(),
      map_path.c_str(), gt.poses.empty() ? "" : (", " + plot_dir + "/").c_str(),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count());
  return 0;
}

}  // namespace

int RunRunOrStereoCommand(const std::vector<std::string>& args) {
  std::string pipeline = "laser";
  std::string error;
  if (!FLAGS_config.empty() &&
      !ReadRunPipeline(FLAGS_config, &pipeline, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (pipeline == "laser") return RunRunCommand(args);
  if (pipeline != "stereo") {
    std::cerr << FLAGS_config << ": run.pipeline '" << pipeline
              << "' is not a pipeline (laser, stereo)\n";
    return 2;
  }
  if (!args.empty()) {
    std::cerr << "run: unexpected argument '" << args[0] << "'\n";
    return 2;
  }
  StereoRunConfig config;
  if (!LoadStereoRunConfig(FLAGS_config, &config, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (!FLAGS_output_dir.empty()) config.output_dir = FLAGS_output_dir;
  if (FLAGS_dump_config) {
    std::cout << StereoRunConfigToYaml(config);
    return 0;
  }
  if (config.sequence.empty()) {
    std::cerr << "run: no sequence folder named (run.sequence in --config)\n";
    return 2;
  }
  return RunStereo(config);
}

}  // namespace slam
