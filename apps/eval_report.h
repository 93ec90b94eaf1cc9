// Evaluating an estimate against a ground truth and reporting it: the table
// printed on stdout, the JSON objects of the report, the plots, and the
// `eval:` YAML section (eval_config.h). `slam eval` uses it, and so does every
// command that evaluates its own result in the same run (`slam optimize --gt`):
//
//   TrajectoryData gt;  // datasets/trajectory_io.h
//   ReadTrajectory(FLAGS_gt, {}, &gt, &error);
//   Trajectory est;
//   TrajectoryFromGraph(graph, false, &est, &error);  // stamps = node ids
//   EvalSettings settings;  // core/metrics/ (+ ReadEvalSettingsYaml)
//   settings.association = ChooseAssociation(gt.has_stamps, true);
//   EvalResult result;
//   if (!EvaluateAndReport(gt.poses, est, settings, FLAGS_plot, std::cout,
//                          &result, &error)) { ... }
//   report.Add("evaluation", EvalResultJson(result, settings));
#ifndef SLAM_APPS_EVAL_REPORT_H_
#define SLAM_APPS_EVAL_REPORT_H_

#include <ostream>
#include <string>
#include <vector>

#include "apps/eval_config.h"
#include "apps/json.h"
#include "core/graph.h"
#include "core/metrics/evaluation.h"
#include "core/trajectory.h"
#include "datasets/trajectory_io.h"

namespace slam {

// Names used in the printed table and the plots.
struct EvalLabels {
  std::string ref_name = "reference";
  std::string est_name = "estimate";
};

// Evaluates (core EvaluateTrajectories), prints the association, the applied
// alignment and the table of results to `out`, and writes the plots into
// plot_dir when it is not empty (created if needed). False with a message.
bool EvaluateAndReport(const Trajectory& ref, const Trajectory& est,
                       const EvalSettings& settings,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error);
bool EvaluateAndReport(const Trajectory& ref, const Trajectory& est,
                       const EvalSettings& settings, const EvalLabels& labels,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error);
// The trajectories as read (datasets/trajectory_io.h ToEvalTrajectory: evo's
// float64 stamps, KITTI matrices as read).
bool EvaluateAndReport(const EvalTrajectory& ref, const EvalTrajectory& est,
                       const EvalSettings& settings, const EvalLabels& labels,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error);

// `slam optimize --gt`: evaluates the pose nodes of `graph` (stamped by node
// id, in seconds, as `slam simulate` stamps its ground truth) against `gt`
// (read from gt_name) with the `eval:` section of config_path (may be
// empty), prints under "evaluation against GT_NAME:", plots into plot_dir
// when not empty, and adds "evaluation" to *report.
bool EvaluateGraphAgainstGroundTruth(const Graph& graph,
                                     const TrajectoryData& gt,
                                     const std::string& gt_name,
                                     const std::string& config_path,
                                     const std::string& plot_dir,
                                     JsonObject* report, std::string* error);

// Index association when either side has no stamps (KITTI without times).
AssociationMethod ChooseAssociation(bool ref_has_stamps, bool est_has_stamps);

// Human-readable parts.
void PrintAssociationAndAlignment(const EvalResult& result,
                                  const EvalSettings& settings,
                                  std::ostream& out);
void PrintEvalTable(const EvalResult& result, const EvalSettings& settings,
                    std::ostream& out);

// JSON: the settings, and the results ("matched_pairs", "association",
// "alignment", "ape_translation", "ape_rotation", "rpe_translation",
// "rpe_rotation", "path_length", and "kitti" when computed). Each statistics
// object holds rmse, mean, median, std, min, max, sse, count and unit.
JsonObject EvalSettingsJson(const EvalSettings& settings);
JsonObject EvalResultJson(const EvalResult& result,
                          const EvalSettings& settings);
// The same entries added to an existing object (e.g. a command's report).
void AddEvalResultJson(const EvalResult& result, const EvalSettings& settings,
                       JsonObject* out);
JsonObject StatisticsJson(const ErrorStatistics& stats, const char* unit);

// Plots written into `dir` (PNG), by the plot module (apps/plot_module.h):
// trajectories.png (reference and aligned estimate on the plane of the two
// axes of largest extent),
// ape_map.png (estimate coloured by the APE with a colour bar), ape.png (APE
// over time, translation and rotation), rpe.png (RPE over time). The names
// written are appended to *written.
bool WriteEvalPlots(const std::string& dir, const EvalResult& result,
                    const EvalSettings& settings, const EvalLabels& labels,
                    std::vector<std::string>* written, std::string* error);
// The implementation inside the plot module.
bool WriteEvalPlotsImpl(const std::string& dir, const EvalResult& result,
                        const EvalSettings& settings, const EvalLabels& labels,
                        std::vector<std::string>* written, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_EVAL_REPORT_H_
