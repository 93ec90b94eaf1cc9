// The KITTI odometry devkit's segment metric.
//
// KITTI odometry metric (devkit_odometry evaluate_odometry.cpp,
//   calcSequenceErrors + saveStats): reference path distances; for every
//   first frame 0, 10, 20, ... (step_size 10 frames) and every length L in
//   {100, ..., 800} m the last frame is the first whose distance exceeds
//   dist[first] + L (the segment is skipped when there is none); error pose
//   E = (P_f^-1 P_l)^-1 (Q_f^-1 Q_l); t_err = |t(E)| / L, r_err = acos(
//   clamp(0.5 (trace(R(E)) - 1))) / L. The result is the mean over all
//   segments (all lengths together, not a mean of per-length means):
//   t_rel_percent = 100 mean(t_err), r_rel_deg_per_100m = mean(r_err) * 180
//   / pi * 100. The devkit computes distances, the per-segment errors and
//   their sums in single precision (float); we do the same, so that segment
//   choice and rounding follow the devkit's. The devkit never aligns: the
//   metric uses the estimate as read, except with a scale alignment (sim3,
//   scale), where it uses the scaled estimate (rigid alignments do not change
//   relative poses).
#ifndef SLAM_CORE_METRICS_KITTI_METRIC_H_
#define SLAM_CORE_METRICS_KITTI_METRIC_H_

#include <cstddef>
#include <string>
#include <vector>

#include "core/lie.h"
#include "core/metrics/matrix_pose.h"

namespace slam {

// Devkit segment and summary; t_err in m/m, r_err in rad/m (as the devkit).
struct KittiSegmentError {
  size_t first_frame = 0;
  size_t last_frame = 0;
  double length = 0.0;
  double t_err = 0.0;
  double r_err = 0.0;
};
struct KittiLengthSummary {
  double length = 0.0;
  size_t count = 0;
  double t_rel_percent = 0.0;
  double r_rel_deg_per_100m = 0.0;
};
struct KittiMetric {
  size_t num_segments = 0;  // 0: trajectory shorter than 100 m (values NaN).
  double t_rel_percent = 0.0;
  double r_rel_deg_per_100m = 0.0;
  std::vector<KittiLengthSummary> by_length;  // Lengths with segments.
  std::vector<KittiSegmentError> segments;
};
// ref/est matched (same size), frame k of both at index k.
bool ComputeKittiMetric(const std::vector<MatrixPose>& ref,
                        const std::vector<MatrixPose>& est, KittiMetric* metric,
                        std::string* error);
bool ComputeKittiMetric(const std::vector<Pose3>& ref,
                        const std::vector<Pose3>& est, KittiMetric* metric,
                        std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_KITTI_METRIC_H_
