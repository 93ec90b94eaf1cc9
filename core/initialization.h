// Initial guesses for pose graphs, computed from the relative-pose (between)
// factors. Every method keeps the anchor nodes where they are: the fixed
// nodes if any, else the first node (lowest key) of each connected component.
//
//   kNone          keep the values as they are (e.g. as read from the file).
//   kOdometry      compose the measurements along increasing ids
//                  (X_{k+1} = X_k Z_{k,k+1}); nodes the chain does not reach
//                  are reached breadth-first through any between factor.
//   kSpanningTree  breadth-first from the anchors through all between factors,
//                  each node set by the first factor that reaches it (g2o's
//                  -guess with unit edge cost).
//   kChordal       chordal relaxation (Carlone et al., ICRA 2015): rotations
//                  first, as an unconstrained linear least-squares problem over
//                  rotation-matrix entries projected back onto SO(2)/SO(3);
//                  then two Gauss-Newton steps on the rotations alone
//                  (2D: the wrapped heading errors; 3D: Log of the rotation
//                  errors), then translations by linear least squares with
//                  the rotations held fixed.
#ifndef SLAM_CORE_INITIALIZATION_H_
#define SLAM_CORE_INITIALIZATION_H_

#include <set>
#include <string>

#include "core/graph.h"

namespace slam {

enum class InitMethod { kNone, kOdometry, kSpanningTree, kChordal };
const char* InitMethodName(InitMethod method);
bool ParseInitMethod(const std::string& text, InitMethod* method);

// How the chordal initialization solves its sparse linear systems: kAuto
// picks from CHOLMOD's symbolic analysis of the node graph (Eigen's
// simplicial LDL^T for sparse factors, CHOLMOD's supernodal LL^T with 64-bit
// indices for dense or huge ones, conjugate gradients when no factor fits);
// the others force a backend (tests).
//   kIterative  Eigen's conjugate gradients on the normal equations,
//               preconditioned by an incomplete Cholesky factor (in node
//               order, which is time order in pose graphs: fewer iterations
//               than AMD's order on simulated worlds; memory of the order of
//               the system itself), to a relative residual of
//               iterative_tolerance. Loop closures between far-apart times
//               fill a direct factor completely but make the graph well
//               connected, which is what conjugate gradients need.
enum class LinearBackend { kAuto, kSimplicial, kSupernodal, kIterative };
const char* LinearBackendName(LinearBackend backend);

struct InitOptions {
  LinearBackend backend = LinearBackend::kAuto;
  // Largest sparse factor the chordal initialization may allocate, in bytes
  // (0: half the physical memory), and the largest factorization cost, in
  // flops (1e12: a few minutes; the 1000 x 1000-lattice 1M-node grid world
  // of scripts/benchmark_load.py needs 5e9). Beyond either, kAuto solves by
  // conjugate gradients (iterative_fallback) or fails with a message giving
  // the factor's size, instead of exhausting the memory or running for
  // hours (dense factors, as from loop closures between random times).
  double max_factor_bytes = 0.0;
  double max_factor_flops = 1e12;
  bool iterative_fallback = true;
  // kIterative: relative residual |b - A x| / |b| to reach, and the most
  // conjugate-gradient iterations per system (not reaching the tolerance
  // within them is an error).
  double iterative_tolerance = 1e-10;
  int max_iterative_iterations = 20000;
};

// What the chordal initialization did (InitializePoses' optional output).
struct InitReport {
  LinearBackend backend = LinearBackend::kAuto;  // The one used.
  int iterative_iterations = 0;  // kIterative: summed over the systems.
  double iterative_error = 0.0;  // kIterative: largest relative residual.
};

// Initializes the pose nodes (SE(2) or SE(3), not mixed) of the graph. If
// `only` is given, only those nodes are written (the others act as already
// known). Returns false with *error when the graph mixes SE(2) and SE(3)
// between factors or a linear system cannot be solved or does not fit.
bool InitializePoses(Graph* graph, InitMethod method, std::string* error,
                     const std::set<Key>* only = nullptr,
                     const InitOptions& options = InitOptions(),
                     InitReport* report = nullptr);

}  // namespace slam

#endif  // SLAM_CORE_INITIALIZATION_H_
