// Settings of `slam run` with `run.pipeline: rgbd` (visual SLAM on a TUM
// RGB-D folder, frontends/rgbd/ feeding frontends/visual/visual_slam.h): a
// plain struct with defaults, loaded from the `run:` section of a YAML file
// (unknown keys are errors) and printable back as YAML (--dump_config). See
// configs/tum_rgbd.yaml.
//
//   run:
//     pipeline: rgbd
//     sequence: rgbd_tum_fr1_rpy_0-109  # folder, relative to the datasets dir
//     ground_truth: ""          # "" = SEQUENCE/groundtruth.txt if present
//     output_dir: out/tum_rgbd
//     max_frames: 0             # associated frames; 0 = all
//     max_time_difference: 0.02 # s, colour-depth association
//     fixed_rate_capture: true  # stamps are arrival times of a fixed-rate
//                               # camera (frontends/visual/capture_clock.h)
//     camera: auto              # freiburg1 | freiburg2 | freiburg3 | custom
//                               # | auto (the preset the folder name says)
//     intrinsics: {fx, fy, cx, cy, k1, k2, p1, p2, k3}  # camera: custom
//     depth: {depth_factor, virtual_baseline, min_depth, max_depth}
//                               # frontends/rgbd/rgbd_features.h
//     features: {...}           # ORB (frontends/stereo/stereo_features.h)
//     tracking: {...}, keyframes: {...}, bundle_adjustment: {...},
//     loop_closure: {...}       # as the stereo pipeline's
//   loops: {...}                # place recognition, as slam loops
// The evaluation against the ground truth follows the file's `eval:` section
// (the keys of `slam eval`; default here: SE(3) alignment, association by
// stamps within 0.02 s, RPE over one frame, and RPE over one second).
#ifndef SLAM_APPS_VISUAL_RGBD_RUN_CONFIG_H_
#define SLAM_APPS_VISUAL_RGBD_RUN_CONFIG_H_

#include <string>

#include "datasets/tum_rgbd_io.h"
#include "frontends/rgbd/rgbd_camera.h"
#include "frontends/rgbd/rgbd_features.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/visual/visual_slam.h"

namespace slam {

struct RgbdRunConfig {
  std::string pipeline = "rgbd";
  std::string sequence;
  std::string ground_truth;
  std::string output_dir = "out/rgbd";
  int max_frames = 0;
  double max_time_difference = 0.02;
  std::string camera = "auto";
  RgbdCamera intrinsics;  // camera: custom.
  RgbdConfig depth;
  StereoFeatureConfig features;  // The ORB settings (no stereo matching).
  VisualSlamConfig slam;
};

bool LoadRgbdRunConfig(const std::string& path, RgbdRunConfig* config,
                       std::string* error);
bool ValidateRgbdRunConfig(const RgbdRunConfig& config, std::string* error);
std::string RgbdRunConfigToYaml(const RgbdRunConfig& config);

// The camera of the run: the preset named, the one the folder name says
// (auto), or the intrinsics (custom); *how says which and why. False with a
// message when auto finds no preset in the name.
bool ChooseRgbdCamera(const RgbdRunConfig& config, const std::string& folder,
                      RgbdCamera* camera, std::string* how, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_RGBD_RUN_CONFIG_H_
