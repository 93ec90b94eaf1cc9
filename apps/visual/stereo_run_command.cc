// slam run with run.pipeline: stereo (visual SLAM on a KITTI-style stereo
// sequence folder: frontends/visual/visual_slam.h fed by
// frontends/stereo/stereo_source.h).
//
//   slam run --config configs/kitti_stereo.yaml [--datasets DIR]
//            [--output_dir DIR] [--gt POSES.txt] [--report FILE.json]
//
// Outputs: apps/visual/visual_run_outputs.h.
#include <gflags/gflags.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/progress_bar.h"
#include "apps/run_config.h"
#include "apps/visual/stereo_run_config.h"
#include "apps/visual/visual_commands.h"
#include "apps/visual/visual_run_outputs.h"
#include "datasets/atomic_file.h"
#include "datasets/kitti_sequence_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/stereo/stereo_source.h"
#include "frontends/visual/visual_slam.h"

DECLARE_string(output_dir);

namespace slam {
namespace {

namespace fs = std::filesystem;

int RunStereo(const StereoRunConfig& config) {
  std::string error;
  VisualRunInfo info;
  info.start = std::chrono::steady_clock::now();
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
  // The images in playback order (forward, or forward then back), numbered
  // and stamped in playback order: the sequence's stamps forward,
  // frame_period apart when played forward and back.
  std::vector<size_t> order;
  for (size_t k = 0; k < available; ++k) order.push_back(k);
  if (config.playback == "forward_backward") {
    for (size_t k = available - 1; k-- > 0;) order.push_back(k);
  }
  std::vector<TimeNs> stamps;
  for (size_t k = 0; k < order.size(); ++k) {
    stamps.push_back(config.playback == "forward"
                         ? sequence.stamps[k]
                         : SecondsToNs(config.frame_period * k));
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
  const std::string gt_path =
      GroundTruthPathOf(config.ground_truth, sequence.ground_truth_path);
  if (!gt_path.empty()) {
    TrajectoryData gt;
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
    for (size_t k : order) info.ground_truth.push_back(gt.poses[k]);
  }
  info.eval.align = AlignmentMethod::kNone;
  info.eval.kitti = true;
  if (!LoadEvalSectionOfConfig(FLAGS_config, &info.eval, &error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  info.eval.association = ChooseAssociation(false, false);

  // Outputs that cannot be written fail before the work. The output folder
  // is made now and removed again if the run fails or is stopped
  // (datasets/atomic_file.h); the report may go into it.
  if (!CreateOutputFolder(config.output_dir, &error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  if (!FLAGS_report.empty() && !CheckOutputFile(FLAGS_report, &error)) {
    std::cerr << "run: --report " << error << "\n";
    return 1;
  }

  // The first pair fixes the image size (checked against the calibration).
  StereoSequenceSource source(&sequence, order, stamps, config.features);
  if (!source.Open(&error)) {
    std::cerr << "run: " << error << "\n";
    return 1;
  }
  VisualSlamConfig slam_config;
  slam_config.odometry = config.odometry;
  slam_config.loop_closure = config.loop_closure;
  slam_config.loops = config.loops;
  info.pipeline = "stereo";
  info.sequence = dir;
  info.output_dir = config.output_dir;
  info.loop_closure_enabled = config.loop_closure.enabled;
  return RunVisualSlamAndWrite(slam_config, source, info);
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
  if (pipeline == "rgbd") return RunRgbdCommand(args);
  if (pipeline != "stereo") {
    std::cerr << FLAGS_config << ": run.pipeline '" << pipeline
              << "' is not a pipeline (laser, stereo, rgbd)\n";
    return 2;
  }
  return RunVisualCommand<StereoRunConfig>(args, LoadStereoRunConfig,
                                           StereoRunConfigToYaml, RunStereo);
}

}  // namespace slam
