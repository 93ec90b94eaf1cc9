// slam optimize --marginals: the node ids of the flag, their pose keys in a
// graph, and the printed and reported marginal covariances
// (core/marginals.h).
#ifndef SLAM_APPS_MARGINALS_REPORT_H_
#define SLAM_APPS_MARGINALS_REPORT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "apps/json.h"
#include "core/graph.h"

namespace slam {

// Parses "ID,ID,..." (empty text: no ids). False with *error naming the
// item that is not a node id.
bool ParseMarginalIds(const std::string& text, std::vector<int64_t>* ids,
                      std::string* error);

// The pose key (2D or 3D; the file's single id space) of every id. False
// with *error when an id names no pose node of the graph read from `input`.
bool MarginalKeysOf(const Graph& graph, const std::vector<int64_t>& ids,
                    const std::string& input, std::vector<Key>* keys,
                    std::string* error);

// Computes the marginal covariances of `keys` (none: does nothing), prints
// them and adds each, row-major, to *json under its node id.
bool ReportMarginals(Graph* graph, const std::vector<Key>& keys,
                     JsonObject* json, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_MARGINALS_REPORT_H_
