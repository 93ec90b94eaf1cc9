#include "core/metrics/evaluation.h"

#include "core/metrics/format.h"

namespace slam {

namespace {

using metrics_internal::Format;

// The stamps only (for messages).
Trajectory StampsOnly(const EvalTrajectory& t) {
  Trajectory out(t.size());
  for (size_t i = 0; i < t.size(); ++i) out[i].stamp = t.stamps[i];
  return out;
}

}  // namespace

bool EvaluateTrajectories(const Trajectory& ref, const Trajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error) {
  return EvaluateTrajectories(ToEvalTrajectory(ref), ToEvalTrajectory(est),
                              settings, result, error);
}

bool EvaluateTrajectories(const EvalTrajectory& ref, const EvalTrajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error) {
  *result = EvalResult();
  if (ref.empty()) {
    *error = "the reference trajectory has no poses";
    return false;
  }
  if (est.empty()) {
    *error = "the estimated trajectory has no poses";
    return false;
  }
  if (settings.association == AssociationMethod::kIndex) {
    if (!AssociateBySize(ref.size(), est.size(), &result->association, error)) {
      return false;
    }
  } else {
    if (!CheckAssociationOptions(settings.sync, error)) return false;
    result->association = AssociateByTimestamp(ref, est, settings.sync);
    if (result->association.size() == 0) {
      *error =
          "found no matching timestamps between the reference and the "
          "estimate with max. time diff " +
          Format("%g", settings.sync.t_max_diff) + " s and time offset " +
          Format("%g", settings.sync.t_offset) + " s: " +
          ExplainNoTimestampMatches(StampsOnly(ref), StampsOnly(est),
                                    settings.sync);
      return false;
    }
  }
  const Association& a = result->association;
  result->ref.reserve(a.size());
  result->ref_stamps.reserve(a.size());
  result->est.reserve(a.size());
  result->est_stamps.reserve(a.size());
  for (size_t k = 0; k < a.size(); ++k) {
    result->ref.push_back(ref.poses[a.ref_indices[k]]);
    result->ref_stamps.push_back(ref.stamps[a.ref_indices[k]]);
    result->est.push_back(est.poses[a.est_indices[k]]);
    result->est_stamps.push_back(est.stamps[a.est_indices[k]]);
  }
  if (!ComputeAlignment(result->ref, result->est, settings.align,
                        settings.n_to_align, &result->alignment, error)) {
    *error = "alignment (" + std::string(AlignmentMethodName(settings.align)) +
             ") of " + std::to_string(a.size()) + " matched poses: " + *error;
    return false;
  }
  result->est_aligned = ApplyAlignment(result->alignment, result->est);
  result->ref_path_length = PathLength(result->ref);
  result->est_path_length = PathLength(result->est_aligned);

  result->ape_translation =
      ApeTranslationErrors(result->ref, result->est_aligned);
  result->ape_rotation_deg =
      ApeRotationErrorsDeg(result->ref, result->est_aligned);
  result->ape_translation_stats =
      ComputeErrorStatistics(result->ape_translation);
  result->ape_rotation_stats = ComputeErrorStatistics(result->ape_rotation_deg);

  if (!ComputeRpe(result->ref, result->est_aligned, result->ref_stamps,
                  result->est_stamps, settings.rpe, &result->rpe, error)) {
    return false;
  }
  result->rpe_translation_stats =
      ComputeErrorStatistics(result->rpe.translation);
  result->rpe_rotation_stats = ComputeErrorStatistics(result->rpe.rotation_deg);

  if (settings.kitti) {
    result->has_kitti = true;
    // The devkit does not align; a rigid alignment leaves relative poses
    // unchanged, so only a scale correction is applied (see the header).
    const bool scaled = settings.align == AlignmentMethod::kSim3 ||
                        settings.align == AlignmentMethod::kScale;
    if (!ComputeKittiMetric(result->ref,
                            scaled ? result->est_aligned : result->est,
                            &result->kitti, error)) {
      return false;
    }
  }
  return true;
}

}  // namespace slam
