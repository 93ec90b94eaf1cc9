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

// `num_nodes` nodes and `edges`, the (i, j) pairs of nodes sharing a factor.
// `methods` is "auto" (best of AMD, METIS, NESDIS) or one of those names.
// The machine's physical memory in bytes (0 if unknown): the default budget
// of the sparse factors (half of it).
double PhysicalMemoryBytes();

bool FillReducingOrdering(int num_nodes,
                          const std::vector<std::pair<int, int>>& edges,
                          const std::string& methods, OrderingResult* result,
                          std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_ORDERING_H_
