// The YAML description (apps/config_schema.h) of the settings every visual
// SLAM pipeline of `slam run` shares (frontends/visual/visual_slam.h): the
// ORB detector's keys of the `features:` section and the `tracking:`,
// `keyframes:`, `bundle_adjustment:` and `loop_closure:` sections, so that
// the stereo and the RGB-D configs read them with one description.
#ifndef SLAM_APPS_VISUAL_VISUAL_SLAM_CONFIG_H_
#define SLAM_APPS_VISUAL_VISUAL_SLAM_CONFIG_H_

#include <string>
#include <vector>

#include "apps/config_schema.h"
#include "apps/visual/loops_config.h"
#include "frontends/stereo/stereo_features.h"
#include "frontends/stereo/stereo_loop_closing.h"
#include "frontends/stereo/stereo_odometry.h"

namespace slam {

// max_features, scale_factor, levels, fast_threshold, cell_size,
// max_per_cell, grid_fast, min_fast_threshold.
std::vector<config_schema::Field> OrbFeatureFields(StereoFeatureConfig* f);

// tracking, keyframes, bundle_adjustment, loop_closure.
std::vector<config_schema::Section> VisualSlamSections(
    StereoOdometryConfig* odometry, StereoLoopClosingConfig* loop_closure);

// After the run: section is read: the file's `loops:` section (its
// verification set to PnP on the keyframes' points, which have depth), and
// the noise model's pyramid scale from the features.
bool LoadVisualSlamExtras(const std::string& path,
                          const StereoFeatureConfig& features,
                          StereoOdometryConfig* odometry, LoopsConfig* loops,
                          std::string* error);

// The ranges of the shared settings; false with "section: problem".
bool ValidateVisualSlamSettings(const StereoOdometryConfig& odometry,
                                const StereoLoopClosingConfig& loop_closure,
                                const LoopsConfig& loops, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_VISUAL_SLAM_CONFIG_H_
