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

#include <chrono>
#include <string>

#include "core/evaluation.h"
#include "core/trajectory.h"
#include "frontends/visual/visual_slam.h"

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
  std::chrono::steady_clock::time_point start;  // Of the command.
};

// Writes the outputs, prints the summary and the evaluation, writes the
// --report JSON. 0, or 1 after printing "run: problem" on stderr.
int WriteVisualRun(const VisualRunInfo& info, const VisualSlam& slam,
                   const VisualSlamResult& result);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_VISUAL_RUN_OUTPUTS_H_
