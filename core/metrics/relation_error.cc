#include "core/metrics/relation_error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>

#include "core/metrics/matrix_pose.h"

namespace slam {

namespace {

// The pose of `est` at `stamp` (see ComputeRelationError); false when there
// is none. *interpolated tells which way it was found.
bool PoseAt(const Trajectory& est, TimeNs stamp,
            const RelationErrorOptions& options, Pose3* pose,
            bool* interpolated) {
  const auto later = std::lower_bound(
      est.begin(), est.end(), stamp,
      [](const StampedPose& p, TimeNs t) { return p.stamp < t; });
  // Nearest stamp: the first at or after `stamp`, or the one before.
  auto nearest = later;
  if (later == est.end() ||
      (later != est.begin() &&
       stamp - std::prev(later)->stamp <= later->stamp - stamp)) {
    nearest = std::prev(later);
  }
  const double dt = std::fabs(NsToSeconds(nearest->stamp - stamp));
  if (dt <= options.t_max_diff) {
    *pose = nearest->pose;
    *interpolated = false;
    return true;
  }
  if (!options.interpolate || later == est.end() || later == est.begin()) {
    return false;
  }
  const StampedPose& a = *std::prev(later);
  const StampedPose& b = *later;
  const double f = static_cast<double>(stamp - a.stamp) /
                   static_cast<double>(b.stamp - a.stamp);
  *pose =
      Pose3(a.pose.t + f * (b.pose.t - a.pose.t), a.pose.q.slerp(f, b.pose.q));
  *interpolated = true;
  return true;
}

std::string SecondsText(TimeNs t) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6f", NsToSeconds(t));
  return buf;
}

}  // namespace

bool ComputeRelationError(const Trajectory& est,
                          const std::vector<PoseRelation>& relations,
                          const RelationErrorOptions& options,
                          RelationErrorResult* result, std::string* error) {
  *result = RelationErrorResult();
  result->relations = relations.size();
  if (!(options.t_max_diff >= 0.0)) {
    *error = "relations: t_max_diff must be >= 0";
    return false;
  }
  if (est.empty()) {
    *error = "relations: the estimate has no poses";
    return false;
  }
  for (size_t i = 1; i < est.size(); ++i) {
    if (est[i].stamp <= est[i - 1].stamp) {
      *error =
          "relations: the estimate's stamps must increase strictly (pose " +
          std::to_string(i) + " at " + SecondsText(est[i].stamp) + " s after " +
          SecondsText(est[i - 1].stamp) + " s)";
      return false;
    }
  }
  std::vector<double> translation_sq, rotation_sq;
  for (size_t k = 0; k < relations.size(); ++k) {
    const PoseRelation& r = relations[k];
    Pose3 x1, x2;
    bool i1 = false, i2 = false;
    if (!PoseAt(est, r.t1, options, &x1, &i1) ||
        !PoseAt(est, r.t2, options, &x2, &i2)) {
      ++result->unmatched;
      continue;
    }
    const Pose3 e = r.delta.Inverse() * (x1.Inverse() * x2);
    const double t = e.t.norm();
    const double rot = RotationAngle(e.q) * 180.0 / M_PI;
    result->used.push_back(k);
    result->interpolated += (i1 || i2) ? 1 : 0;
    result->translation.push_back(t);
    result->rotation_deg.push_back(rot);
    translation_sq.push_back(t * t);
    rotation_sq.push_back(rot * rot);
  }
  if (result->used.empty()) {
    *error = "relations: none of the " + std::to_string(relations.size()) +
             " relations has poses in the estimate (estimate stamps " +
             SecondsText(est.front().stamp) + " .. " +
             SecondsText(est.back().stamp) + " s";
    if (!relations.empty()) {
      *error += ", first relation " + SecondsText(relations.front().t1) +
                " -> " + SecondsText(relations.front().t2) + " s";
    }
    *error += options.interpolate
                  ? ")"
                  : "; stamps must match within " +
                        SecondsText(SecondsToNs(options.t_max_diff)) +
                        " s, or interpolate)";
    return false;
  }
  result->translation_abs = ComputeMeanStd(result->translation);
  result->translation_sq = ComputeMeanStd(translation_sq);
  result->rotation_abs = ComputeMeanStd(result->rotation_deg);
  result->rotation_sq = ComputeMeanStd(rotation_sq);
  return true;
}

}  // namespace slam
