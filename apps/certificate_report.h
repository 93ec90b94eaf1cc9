// slam optimize --certify: the pose-graph certificate of global optimality
// (core/certificate.h) after the solve, the staircase escape when it fails
// (--global auto), the printed lines and the report's certificate block.
#ifndef SLAM_APPS_CERTIFICATE_REPORT_H_
#define SLAM_APPS_CERTIFICATE_REPORT_H_

#include <string>

#include "apps/json.h"
#include "core/graph.h"
#include "core/optimizer.h"

namespace slam {

// Does nothing without --certify. Else certifies the graph's values; when
// that fails and --global is auto, runs the staircase, LM on the full
// objective from its rounded solution (counted in *summary), keeps the
// better of the two LM solutions by chi2 and certifies again. Fills *json
// with the certificate block (not_available: why, on graphs it does not
// cover: the solve stands). False with *error on a failure to run.
bool CertifyIfAsked(Graph* graph, const OptimizerOptions& options,
                    OptimizerSummary* summary, JsonObject* json,
                    std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_CERTIFICATE_REPORT_H_
