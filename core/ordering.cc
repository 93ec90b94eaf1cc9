#include "core/ordering.h"

#include <algorithm>

#include <cholmod.h>
#include <unistd.h>

namespace slam {

double PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGESIZE);
  return pages > 0 && page_size > 0
             ? static_cast<double>(pages) * static_cast<double>(page_size)
             : 0.0;
}

double FactorExcess(double nonzeros, double flops, double max_bytes,
                    double max_flops) {
  const double budget =
      max_bytes > 0.0 ? max_bytes : 0.5 * PhysicalMemoryBytes();
  const double bytes = nonzeros * sizeof(double);
  return std::max(budget > 0.0 ? bytes / budget : 0.0, flops / max_flops);
}

bool FillReducingOrdering(int num_nodes,
                          const std::vector<std::pair<int, int>>& edges,
                          const std::string& methods, OrderingResult* result,
                          std::string* error) {
  if (num_nodes == 0) {
    result->order.clear();
    result->method = "natural";
    return true;
  }
  // Upper-triangular pattern (stype = 1), column-compressed, with diagonal.
  std::vector<std::vector<int>> rows(num_nodes);
  for (int j = 0; j < num_nodes; ++j) rows[j].push_back(j);
  for (const auto& [a, b] : edges) {
    if (a == b) continue;
    rows[std::max(a, b)].push_back(std::min(a, b));
  }
  size_t nnz = 0;
  for (auto& r : rows) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    nnz += r.size();
  }
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.supernodal = CHOLMOD_SIMPLICIAL;
  if (methods == "auto") {
    common.nmethods = 3;
    common.method[0].ordering = CHOLMOD_AMD;
    common.method[1].ordering = CHOLMOD_METIS;
    common.method[2].ordering = CHOLMOD_NESDIS;
  } else {
    common.nmethods = 1;
    if (methods == "amd") {
      common.method[0].ordering = CHOLMOD_AMD;
    } else if (methods == "metis") {
      common.method[0].ordering = CHOLMOD_METIS;
    } else if (methods == "nesdis") {
      common.method[0].ordering = CHOLMOD_NESDIS;
    } else {
      cholmod_finish(&common);
      *error = "unknown ordering '" + methods +
               "' (expected auto, amd, metis or nesdis)";
      return false;
    }
  }
  common.postorder = 1;
  cholmod_sparse* a =
      cholmod_allocate_sparse(num_nodes, num_nodes, nnz,
                              /*sorted=*/1, /*packed=*/1,
                              /*stype=*/1, CHOLMOD_PATTERN, &common);
  if (a == nullptr) {
    cholmod_finish(&common);
    *error = "CHOLMOD could not allocate the ordering pattern";
    return false;
  }
  int* col_ptr = static_cast<int*>(a->p);
  int* row_idx = static_cast<int*>(a->i);
  col_ptr[0] = 0;
  size_t k = 0;
  for (int j = 0; j < num_nodes; ++j) {
    for (int r : rows[j]) row_idx[k++] = r;
    col_ptr[j + 1] = static_cast<int>(k);
  }
  cholmod_factor* factor = cholmod_analyze(a, &common);
  bool ok = factor != nullptr && common.status == CHOLMOD_OK;
  if (ok) {
    const int* perm = static_cast<const int*>(factor->Perm);
    result->order.assign(perm, perm + num_nodes);
    switch (common.method[common.selected].ordering) {
      case CHOLMOD_AMD:
        result->method = "amd";
        break;
      case CHOLMOD_METIS:
        result->method = "metis";
        break;
      case CHOLMOD_NESDIS:
        result->method = "nesdis";
        break;
      default:
        result->method = "other";
        break;
    }
    result->factor_nonzeros = common.lnz;
    result->factor_flops = common.fl;
  } else {
    *error = "CHOLMOD failed to compute an ordering (status " +
             std::to_string(common.status) + ")";
  }
  if (factor != nullptr) cholmod_free_factor(&factor, &common);
  cholmod_free_sparse(&a, &common);
  cholmod_finish(&common);
  return ok;
}

}  // namespace slam
