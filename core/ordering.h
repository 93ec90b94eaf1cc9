// Fill-reducing elimination orderings for the sparse Cholesky factorization
// of the normal equations.
//
// Ceres 2.1 orders SPARSE_NORMAL_CHOLESKY problems with (constrained)
// approximate minimum degree. On pose graphs with many loop closures (3D
// spheres and tori, city grids) nested dissection produces much less fill.
// This asks CHOLMOD (with METIS) to analyse the node-level sparsity pattern
// with several methods and keeps the one with the fewest nonzeros in the
// factor; the optimizer hands the result to Ceres as a complete elimination
// order (one group per parameter block).
#ifndef SLAM_CORE_ORDERING_H_
#define SLAM_CORE_ORDERING_H_

#include <string>
#include <utility>
#include <vector>

namespace slam {

struct OrderingResult {
  std::vector<int> order;        // Node indices in elimination order.
  std::string method;            // "amd", "metis", "nesdis" or "natural".
  double factor_nonzeros = 0.0;  // nnz(L) of the node-level pattern.
  double factor_flops = 0.0;     // Flops of its Cholesky factorization.
};

// The machine's physical memory in bytes (0 if unknown).
double PhysicalMemoryBytes();

// How far a scalar sparse factor of `nonzeros` entries costing `flops` is
// beyond the limits (max_bytes 0: half the physical memory); <= 1: it fits.
// The initialization and the optimizer share these limits.
double FactorExcess(double nonzeros, double flops, double max_bytes,
                    double max_flops);
// AMD's factor more than this many times beyond the limits: METIS and
// nested dissection (2-5x better on grids) cannot bring it within, and are
// slow on such graphs, so they are not tried.
constexpr double kNoOrderingHelps = 10.0;

// `num_nodes` nodes and `edges`, the (i, j) pairs of nodes sharing a factor.
// `methods` is "auto" (best of AMD, METIS, NESDIS) or one of those names.
bool FillReducingOrdering(int num_nodes,
                          const std::vector<std::pair<int, int>>& edges,
                          const std::string& methods, OrderingResult* result,
                          std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_ORDERING_H_
