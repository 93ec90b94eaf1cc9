// How `slam optimize` solves a graph read from a file (pose graphs,
// landmark SLAM, bundle adjustment): which initialization to start from, and
// the staged solve of landmark SLAM from dead reckoning. Steps:
//   1. InitializeGraph: the configured initialization, or with "auto" the
//      better (lower robust chi2) of the file's guess and the chordal
//      relaxation (the spanning tree when the relative-pose factors form a
//      forest); graphs without relative-pose factors keep their values;
//      landmarks given no values follow the poses.
//   2. OptimizeGraph: OptimizeInStages over growing prefixes of the
//      trajectory when asked, then the batch solve.
// Progress lines go to stdout (printf), as the command prints them.
#ifndef SLAM_FRONTENDS_POSEGRAPH_GRAPH_SOLVE_H_
#define SLAM_FRONTENDS_POSEGRAPH_GRAPH_SOLVE_H_

#include <ostream>
#include <string>

#include "core/graph.h"
#include "core/initialization.h"
#include "core/optimizer.h"

namespace slam {

// The initialization's limits on sparse factors are the optimizer's.
InitOptions InitOptionsOf(const OptimizerOptions& optimizer);

// Runs the configured initialization (`init`: auto or an InitMethod name);
// *used: the name of what was used. Graphs without relative-pose factors
// (bundle adjustment) keep their poses.
bool InitializeGraph(const std::string& init, bool landmarks_from_observations,
                     const InitOptions& options, Graph* graph,
                     std::string* used, std::string* error);

// Landmark SLAM from dead reckoning (an odometry tree, landmarks placed at
// their first sightings): solved over growing prefixes of the trajectory
// (poses by id, which is time in these files), 1/2^(stages-1), ..., 1/2 of
// the poses, then all. After each prefix the poses beyond it are composed
// again from the optimized end of the prefix and the landmarks first seen
// beyond it are placed again from the optimized poses. Victoria Park: one
// batch solve from dead reckoning stops in a local minimum (chi2 503277,
// landmarks up to 265 m off) where every batch solver tried stays; solving
// the first half first places the landmarks of the second half well enough
// that the batch reaches the good minimum (6183.93, as incremental iSAM).
// Returns the summed iterations of the prefix solves.
int OptimizeInStages(int stages, const OptimizerOptions& options, Graph* graph);

// Optimize (core/optimizer.h), after OptimizeInStages when stages > 1: the
// summary then counts the iterations of the stages too and its initial chi2
// is the one before them.
OptimizerSummary OptimizeGraph(int stages, const OptimizerOptions& options,
                               Graph* graph, std::ostream* log);

}  // namespace slam

#endif  // SLAM_FRONTENDS_POSEGRAPH_GRAPH_SOLVE_H_
