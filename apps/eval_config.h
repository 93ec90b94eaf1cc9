// The `eval:` section of a YAML config: the evaluation settings
// (core/metrics/evaluation.h EvalSettings) read from and written as YAML.
#ifndef SLAM_APPS_EVAL_CONFIG_H_
#define SLAM_APPS_EVAL_CONFIG_H_

#include <string>

#include <yaml-cpp/yaml.h>

#include "core/metrics/evaluation.h"

namespace slam {

// The `eval:` section of a YAML config. Keys: associate (auto|time|index),
// t_max_diff, t_offset, unique_pairs, align (none|se3|sim3|scale|origin),
// n_to_align, rpe_delta, rpe_unit (frames|m|s), rpe_all_pairs,
// rpe_pairs_from_reference, rpe_delta_tol, kitti, relations_t_max_diff,
// relations_interpolate (for slam eval --relations). Unknown keys are errors.
// *associate_auto is set when associate is auto (the caller decides from the
// stamps).
bool ReadEvalSettingsYaml(const YAML::Node& node, const std::string& where,
                          EvalSettings* settings, bool* associate_auto,
                          std::string* error);
// The `eval:` section of the YAML config file `config_path` (empty: none)
// into *settings, for commands that evaluate as a side job (optimize --gt,
// inertial --gt). Leaves *settings alone when there is no such section.
bool LoadEvalSectionOfConfig(const std::string& config_path,
                             EvalSettings* settings, std::string* error);
// The same keys as YAML text (each line indented by `indent` spaces).
std::string EvalSettingsYaml(const EvalSettings& settings, bool associate_auto,
                             int indent);

// The ranges the evaluation needs: t_max_diff and relations_t_max_diff >= 0,
// a finite t_offset, rpe_delta > 0, rpe_delta_tol >= 0. False with a message
// naming the setting.
bool CheckEvalSettings(const EvalSettings& settings, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_EVAL_CONFIG_H_
