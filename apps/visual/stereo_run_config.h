// Settings of `slam run` with `run.pipeline: stereo` (stereo visual odometry
// on a KITTI-style folder, frontends/stereo/): a plain struct with defaults,
// loaded from the `run:` section of a YAML file (unknown keys are errors) and
// printable back as YAML (--dump_config). See configs/kitti_stereo.yaml.
//
//   run:
//     pipeline: stereo
//     sequence: stereo_kitti06_half   # folder, relative to the datasets dir
//     ground_truth: ""                # "" = SEQUENCE/poses.txt if present
//     output_dir: out/kitti06
//     frame_period: 0.1               # s per frame without times.txt
//     max_frames: 0                   # 0 = all
//     features: {...}                 # frontends/stereo/stereo_features.h
//     tracking: {...}, keyframes: {...}, bundle_adjustment: {...}
//                                     # frontends/stereo/stereo_odometry.h
//     loop_closure: {...}             # frontends/stereo/stereo_loop_closing.h
//   loops: {...}                      # place recognition, as slam loops
// The evaluation against the ground truth follows the file's `eval:` section
// (the keys of `slam eval`, apps/eval_report.h).
#ifndef SLAM_APPS_VISUAL_STEREO_RUN_CONFIG_H_
#define SLAM_APPS_VISUAL_STEREO_RUN_CONFIG_H_

#include <string>

#include "apps/visual/loops_config.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_loop_closing.h"
#include "frontends/stereo/stereo_odometry.h"

namespace slam {

struct StereoRunConfig {
  std::string pipeline = "stereo";
  std::string sequence;
  std::string ground_truth;
  std::string output_dir = "out/stereo";
  double frame_period = 0.1;
  int max_frames = 0;
  // "forward", or "forward_backward": frames 0..n-1 then n-2..0 (a loop
  // test on a sequence without one; stamps continue, the ground truth is
  // played the same way).
  std::string playback = "forward";
  StereoFeatureConfig features;
  StereoOdometryConfig odometry;
  StereoLoopClosingConfig loop_closure;
  // Place recognition: the file's `loops:` section (apps/visual/
  // loops_config.h; its vocabulary, or one trained on the keyframes;
  // verification is always stereo PnP here, orb_features is not used: the
  // keyframes' own features are).
  LoopsConfig loops;
};

// The `pipeline` value of a config's run: section ("laser" when absent);
// false with "FILE:LINE: problem" when the file cannot be read.
bool ReadRunPipeline(const std::string& path, std::string* pipeline,
                     std::string* error);

bool LoadStereoRunConfig(const std::string& path, StereoRunConfig* config,
                         std::string* error);
bool ValidateStereoRunConfig(const StereoRunConfig& config, std::string* error);
std::string StereoRunConfigToYaml(const StereoRunConfig& config);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_STEREO_RUN_CONFIG_H_
