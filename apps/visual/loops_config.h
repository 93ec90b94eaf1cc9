// Settings of visual loop detection (frontends/bow/loop_detector.h) and of
// `slam loops`: a plain struct with defaults, read from the `loops:` section
// of a YAML file and printable back as YAML (--dump_config).
//
//   loops:
//     vocabulary: ""            # binary or DBoW2 .yml/.yml.gz file; empty:
//                               # train one on the sequence itself first
//     vocabulary_k: 10          # self-trained vocabulary: branches
//     vocabulary_levels: 0      # and levels; 0 = the most levels that keep
//                               # at least descriptors_per_word descriptors
//     descriptors_per_word: 20  # per word on average (at most 5 levels)
//     vocabulary_max_descriptors: 200000  # clustered (evenly subsampled)
//     orb_features: 1000        # ORB keypoints per image
//     exclude_recent: 20        # keyframes before the query never matched
//     max_query_results: 50     # database results considered
//     direct_index_levels_up: 2 # direct index this far above the words
//     min_prior_score: 0.005    # score against the previous keyframe
//     prior_keyframes: 2        # best of the last N keyframes (DLoop: 1)
//     min_normalized_score: 0.3 # acceptance threshold (alpha)
//     max_island_gap: 3         # keyframes within an island
//     min_consistent_queries: 3 # consecutive queries agreeing (incl. this)
//     max_island_distance: 3    # keyframes between consecutive islands
//     max_query_gap: 2          # keyframes between consistent queries
//     verification: fundamental # none | fundamental | stereo_pnp
//     match_max_hamming: 50     # descriptor matching (of 256 bits)
//     match_ratio: 0.75         # best / second best distance
//     fundamental_min_inliers: 20
//     fundamental_error_px: 2.0
//     pnp_min_inliers: 20
//     pnp_error_px: 3.0
//     pnp_min_pixel_sigma: 0.5  # floor of the pixel noise (covariance)
//
// The struct, LoopsConfig, is the frontend's (frontends/visual/
// place_recognition.h). The detection defaults are DLoopDetector's
// (frontends/bow/loop_detector.h).
#ifndef SLAM_APPS_VISUAL_LOOPS_CONFIG_H_
#define SLAM_APPS_VISUAL_LOOPS_CONFIG_H_

#include <cstdint>
#include <string>

#include <yaml-cpp/yaml.h>

#include "frontends/bow/loop_detector.h"
#include "frontends/visual/place_recognition.h"

namespace slam {

// Reads the keys of a `loops:` map (node) over *config; `where` names the
// file. Other sections (e.g. a stereo pipeline's loop settings) can reuse it.
bool ReadLoopsConfig(const YAML::Node& node, const std::string& where,
                     LoopsConfig* config, std::string* error);
// Loads the `loops:` section of the YAML file at `path` (absent: defaults).
bool LoadLoopsConfig(const std::string& path, LoopsConfig* config,
                     std::string* error);
bool ValidateLoopsConfig(const LoopsConfig& config, std::string* error);
std::string LoopsConfigToYaml(const LoopsConfig& config);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_LOOPS_CONFIG_H_
