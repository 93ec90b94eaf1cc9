// The relation-based error (Kuemmerle et al. 2009,
// core/metrics/relation_error.h ComputeRelationError) as `slam eval
// --relations` prints it and writes it into the JSON report.
#ifndef SLAM_APPS_RELATION_REPORT_H_
#define SLAM_APPS_RELATION_REPORT_H_

#include <ostream>

#include "apps/json.h"
#include "core/metrics/relation_error.h"

namespace slam {

// The counts and the table: mean +- std of |trans| (m), trans^2 (m^2),
// |rot| (deg), rot^2 (deg^2).
void PrintRelationError(const RelationErrorResult& result,
                        const RelationErrorOptions& options, std::ostream& out);

// {"relations", "used", "unmatched", "interpolated", "t_max_diff",
//  "interpolate", "translation_abs": {"mean", "std", "unit"},
//  "translation_sq", "rotation_abs", "rotation_sq"}.
JsonObject RelationErrorJson(const RelationErrorResult& result,
                             const RelationErrorOptions& options);

}  // namespace slam

#endif  // SLAM_APPS_RELATION_REPORT_H_
