// The relation-based error of Kuemmerle et al. 2009.
#ifndef SLAM_CORE_METRICS_RELATION_ERROR_H_
#define SLAM_CORE_METRICS_RELATION_ERROR_H_

#include <cstddef>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/metrics/statistics.h"
#include "core/trajectory.h"

namespace slam {

// The metric of Kuemmerle et al. 2009, "On measuring the accuracy of SLAM
// algorithms" (Autonomous Robots 27(4)): ground truth is a set of relations
// delta*_ij, the displacement of the pose at t2 in the frame of the pose at
// t1; the error of one relation is
//   e_ij = delta_ij (-) delta*_ij = delta*_ij^-1 delta_ij,
//   delta_ij = x(t1)^-1 x(t2),
// with translational part trans(e_ij) = |t(e_ij)| (metres; equal to
// |t(delta_ij) - t(delta*_ij)|) and rotational part rot(e_ij), the rotation
// angle of e_ij (degrees; |wrap(theta - theta*)| for planar poses). The paper
// defines eps(delta) = 1/N sum trans(e)^2 + rot(e)^2 and its tables (like
// Hess et al. 2016, Table II, computed with Cartographer's
// compute_relations_metrics) give mean +- standard deviation of the absolute
// values |trans|, |rot| and of the squares trans^2, rot^2 over the
// relations, separately. The standard deviation is the sample one (divisor
// N - 1, as compute_relations_metrics; 0 for a single relation).
// Cartographer's tool takes e = delta delta*^-1 instead, whose translation
// norm |t - R R*^T t*| differs from ours by the rotation error times |t*|.
//
// Poses at t1 and t2: the estimate's pose with the nearest stamp when within
// t_max_diff (default 1 ms). Otherwise, with interpolate, the pose
// interpolated between the two neighbouring poses (linear in position, slerp
// in rotation; only inside the trajectory's time range); else the relation
// is counted as unmatched and left out. 2D trajectories are lifted (z = 0,
// rotation about z), so the same code serves SE(2) and SE(3).
struct PoseRelation {
  TimeNs t1 = 0;
  TimeNs t2 = 0;
  Pose3 delta;  // Pose at t2 in the frame of the pose at t1.
};

struct RelationErrorOptions {
  double t_max_diff = 0.001;  // Seconds.
  bool interpolate = false;
};

struct RelationErrorResult {
  size_t relations = 0;             // Given.
  size_t unmatched = 0;             // Left out: a stamp without pose.
  size_t interpolated = 0;          // Used with at least one interpolated pose.
  std::vector<size_t> used;         // Indices of the relations used.
  std::vector<double> translation;  // |trans(e)| per used relation, m.
  std::vector<double> rotation_deg;  // |rot(e)| per used relation, deg.
  MeanStd translation_abs;           // m
  MeanStd translation_sq;            // m^2
  MeanStd rotation_abs;              // deg
  MeanStd rotation_sq;               // deg^2
};

// `est` must have strictly increasing stamps. False with a message when it
// does not, or when no relation could be used (with the time ranges).
bool ComputeRelationError(const Trajectory& est,
                          const std::vector<PoseRelation>& relations,
                          const RelationErrorOptions& options,
                          RelationErrorResult* result, std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_RELATION_ERROR_H_
