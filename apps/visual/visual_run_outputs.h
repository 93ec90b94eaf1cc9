// What `slam run` writes and reports after a visual SLAM run
// (frontends/visual/visual_slam.h), the same for every visual pipeline
// (stereo, rgbd). Outputs in output_dir, all written only after every frame
// was processed (main() publishes them only when the command succeeds):
//   trajectory_kitti.txt  every frame's camera pose, KITTI format
//   trajectory.tum        the same with the frames' stamps
//   graph.g2o             keyframes, map points and their stereo / pinhole
//                         observations (slam optimize reads it back)
//   map_points.ply        the map points (ASCII PLY)
//   map.png               map points and trajectory seen from above
//   timings.csv           per-frame milliseconds by stage
//   plots/                with ground truth: the plots of slam eval --plot
// and on stdout the statistics, the timings by stage (median, p95) and the
// evaluation; --report FILE.json the same as JSON.
#ifndef SLAM_APPS_VISUAL_VISUAL_RUN_OUTPUTS_H_
#define SLAM_APPS_VISUAL_VISUAL_RUN_OUTPUTS_H_

#include <gflags/gflags.h>

#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "apps/common_flags.h"
#include "core/metrics/evaluation.h"
#include "core/trajectory.h"
#include "frontends/visual/visual_slam.h"

DECLARE_string(output_dir);

namespace slam {

struct VisualRunInfo {
  std::string pipeline;  // "stereo" or "rgbd" (the report's pipeline).
  std::string sequence;  // The folder read.
  std::string output_dir;
  std::string camera = "left camera";  // The world frame's camera (PLY).
  std::string est_name = "stereo VO";  // In the evaluation table.
  // The stage that gives the right-image coordinates (name, JSON key).
  std::string matching_stage = "stereo matching";
  std::string matching_key = "stereo_matching";
  bool loop_closure_enabled = false;
  Trajectory ground_truth;  // Empty: no evaluation.
  EvalSettings eval;
  // Also the RPE over one second (TUM's per-second drift), printed after
  // the table and reported as evaluation.rpe_per_second.
  bool rpe_per_second = false;
  std::chrono::steady_clock::time_point start;  // Of the command.
};

// Writes the outputs, prints the summary and the evaluation, writes the
// --report JSON. 0, or 1 after printing "run: problem" on stderr.
int WriteVisualRun(const VisualRunInfo& info, const VisualSlam& slam,
                   const VisualSlamResult& result);

// The work of a visual run once its inputs are read and checked: creates
// info.output_dir, runs the pipeline over the source (progress bar on
// stderr, its lines on stdout; loops.vocabulary resolved against
// --datasets) and writes everything (WriteVisualRun). 0, or 1 after a
// message.
int RunVisualSlamAndWrite(VisualSlamConfig config,
                          const VisualFrameSource& source,
                          const VisualRunInfo& info);

// The ground truth to evaluate against: --gt, else `configured` (relative
// to --datasets), else the folder's own file (`found`, may be "").
std::string GroundTruthPathOf(const std::string& configured,
                              const std::string& found);

// The entry of a visual pipeline's `slam run`: loads the --config into a
// Config (load), applies --output_dir, prints it with --dump_config
// (to_yaml), checks that run.sequence is set, then calls run.
template <typename Config>
int RunVisualCommand(const std::vector<std::string>& args,
                     bool (*load)(const std::string&, Config*, std::string*),
                     std::string (*to_yaml)(const Config&),
                     int (*run)(const Config&)) {
  if (!args.empty()) {
    std::cerr << "run: unexpected argument '" << args[0] << "'\n";
    return 2;
  }
  Config config;
  std::string error;
  if (!load(FLAGS_config, &config, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (!FLAGS_output_dir.empty()) config.output_dir = FLAGS_output_dir;
  if (FLAGS_dump_config) {
    std::cout << to_yaml(config);
    return 0;
  }
  if (config.sequence.empty()) {
    std::cerr << "run: no sequence folder named (run.sequence in --config)\n";
    return 2;
  }
  return run(config);
}

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_VISUAL_RUN_OUTPUTS_H_
