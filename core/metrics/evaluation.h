// Trajectory evaluation: association, alignment and error metrics, defined as
// evo (github.com/MichaelGrupp/evo) and the KITTI odometry devkit define them.
// Pure math: no file format, no command line (datasets/trajectory_io.h reads
// the files, apps/eval_report.h prints and plots).
//
// The definitions, with the evo source each one follows, are in the header of
// each part: matrix_pose.h (poses as read), association.h, alignment.h,
// ape_rpe.h (APE, RPE), statistics.h, kitti_metric.h, relation_error.h.
// This header is the whole pipeline: associate, align, APE, RPE, KITTI.
#ifndef SLAM_CORE_METRICS_EVALUATION_H_
#define SLAM_CORE_METRICS_EVALUATION_H_

#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/metrics/alignment.h"
#include "core/metrics/ape_rpe.h"
#include "core/metrics/association.h"
#include "core/metrics/kitti_metric.h"
#include "core/metrics/matrix_pose.h"
#include "core/metrics/relation_error.h"
#include "core/metrics/statistics.h"
#include "core/trajectory.h"

namespace slam {

enum class AssociationMethod { kTimestamp, kIndex };

struct EvalSettings {
  AssociationMethod association = AssociationMethod::kTimestamp;
  AssociationOptions sync;
  AlignmentMethod align = AlignmentMethod::kSE3;
  int n_to_align = -1;  // <= 0: all pairs.
  RpeOptions rpe;
  bool kitti = false;              // Also the KITTI devkit metric.
  RelationErrorOptions relations;  // slam eval --relations.
};

struct EvalResult {
  Association association;
  // The matched poses, pair k in each; stamps of both (est stamps as read,
  // without the offset).
  std::vector<TimeNs> ref_stamps;
  std::vector<TimeNs> est_stamps;
  std::vector<MatrixPose> ref;
  std::vector<MatrixPose> est;          // As read.
  std::vector<MatrixPose> est_aligned;  // After the alignment.
  Similarity3 alignment;
  double ref_path_length = 0.0;  // Of the matched poses.
  double est_path_length = 0.0;  // Of the matched, aligned poses.

  std::vector<double> ape_translation;   // Per pair, metres.
  std::vector<double> ape_rotation_deg;  // Per pair, degrees.
  ErrorStatistics ape_translation_stats;
  ErrorStatistics ape_rotation_stats;

  RpeErrors rpe;
  ErrorStatistics rpe_translation_stats;
  ErrorStatistics rpe_rotation_stats;

  bool has_kitti = false;
  KittiMetric kitti;
};

// Associates, aligns and computes APE, RPE (and the KITTI metric when asked).
// False with a message (no matching stamps and why, too few pairs, a
// degenerate alignment, no RPE pair for the delta).
bool EvaluateTrajectories(const EvalTrajectory& ref, const EvalTrajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error);
bool EvaluateTrajectories(const Trajectory& ref, const Trajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_EVALUATION_H_
