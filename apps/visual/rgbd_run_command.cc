// slam run with run.pipeline: rgbd (visual SLAM on a TUM RGB-D folder:
// frontends/visual/visual_slam.h fed by frontends/rgbd/rgbd_source.h).
//
//   slam run --config configs/tum_rgbd.yaml [--datasets DIR]
//            [--output_dir DIR] [--gt groundtruth.txt] [--report FILE.json]
//
// Outputs: apps/visual/visual_run_outputs.h (trajectory.tum at the colour
// images' stamps, world = first camera). With a ground truth (the folder's
// groundtruth.txt, run.ground_truth or --gt, TUM format) the evaluation of
// the TUM benchmark: ATE after SE(3) alignment, RPE per frame and per
// second (the eval: section of the config can change it).
#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/progress_bar.h"
#include "apps/run_config.h"
#include "apps/visual/rgbd_run_config.h"
#include "apps/visual/visual_commands.h"
#include "apps/visual/visual_run_outputs.h"
#include "datasets/trajectory_io.h"
#include "datasets/tum_rgbd_io.h"
#include "frontends/rgbd/rgbd_source.h"
#include "frontends/visual/visual_slam.h"

DECLARE_string(output_dir);

namespace slam {
namespace {

namespace fs = std::filesystem;

void PrintUnmatched(const char* what, const std::string& list,
                    const std::vector<TumImageEntry>& unmatched) {
  if (unmatched.empty()) return;
  std::printf(
      "run: %zu %s images without a partner within the time limit "
      "(not used):",
      unmatched.size(), what);
  for (size_t i = 0; i < unmatched.size() && i < 5; ++i) {
    std::printf(" %s:%lld", fs::path(list).filename().c_str(),
                static_cast<long long>(unmatched[i].line));
  }
  std::printf("%s\n", unmatched.size() > 5 ? " ..." : "");
}

int RunRgbd(const RgbdRunConfig& config) {
  std::string error;
  VisualRunInfo info;
  info.start = std::chrono::steady_clock::now();
  auto fail = [](const std::string& message) {
    std::cerr << "run: " << message << "\n";
    return 1;
  };
  const std::string dir = ResolveDatasetPath(config.sequence);
  TumRgbdOptions options;
  options.max_difference = config.max_time_difference;
  TumRgbdSequence sequence;
  if (!ReadTumRgbdSequence(dir, options, &sequence, &error)) return fail(error);
  RgbdCamera camera;
  std::string how;
  if (!ChooseRgbdCamera(config, dir, &camera, &how, &error)) return fail(error);
  RgbdSequenceSource source(&sequence, config.max_frames, camera, config.depth,
                            config.features);
  std::printf(
      "run: rgbd %s: %zu frames of %zu associated colour/depth pairs "
      "(within %g s)\n",
      dir.c_str(), source.NumFrames(), sequence.frames.size(),
      config.max_time_difference);
  PrintUnmatched("colour", sequence.rgb_list, sequence.unmatched_rgb);
  PrintUnmatched("depth", sequence.depth_list, sequence.unmatched_depth);
  std::printf(
      "run: camera %s (%s): fx %.4f fy %.4f cx %.4f cy %.4f, distortion "
      "k1 %g k2 %g p1 %g p2 %g k3 %g; depth factor %g, virtual baseline "
      "%g m\n",
      camera.name.c_str(), how.c_str(), camera.fx, camera.fy, camera.cx,
      camera.cy, camera.k1, camera.k2, camera.p1, camera.p2, camera.k3,
      config.depth.depth_factor, config.depth.virtual_baseline);

  // Ground truth: read (and checked) before the work.
  const std::string gt_path =
      GroundTruthPathOf(config.ground_truth, sequence.ground_truth_path);
  if (!gt_path.empty()) {
    TrajectoryData gt;
    TrajectoryReadOptions read;
    read.format = TrajectoryFormat::kTum;
    if (!ReadTrajectory(gt_path, read, &gt, &error)) return fail(error);
    info.ground_truth = std::move(gt.poses);
  }
  // The TUM benchmark's evaluation: stamps within 0.02 s, SE(3) alignment,
  // RPE over one frame (and over one second, visual_run_outputs.h).
  info.eval.association = AssociationMethod::kTimestamp;
  info.eval.sync.t_max_diff = 0.02;
  info.eval.align = AlignmentMethod::kSE3;
  info.rpe_per_second = true;
  if (!LoadEvalSectionOfConfig(FLAGS_config, &info.eval, &error))
    return fail(error);

  // The first frame fixes the image size (checked against the camera).
  if (!source.Open(&error)) return fail(error);
  info.pipeline = "rgbd";
  info.sequence = dir;
  info.output_dir = config.output_dir;
  info.camera = "camera";
  info.est_name = "RGB-D SLAM";
  info.matching_stage = "depth lookup";
  info.matching_key = "depth_lookup";
  info.loop_closure_enabled = config.slam.loop_closure.enabled;
  return RunVisualSlamAndWrite(config.slam, source, info);
}

}  // namespace

int RunRgbdCommand(const std::vector<std::string>& args) {
  return RunVisualCommand<RgbdRunConfig>(args, LoadRgbdRunConfig,
                                         RgbdRunConfigToYaml, RunRgbd);
}

}  // namespace slam
