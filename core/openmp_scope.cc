#include "core/openmp_scope.h"

#include <omp.h>

#include <cstdlib>

namespace slam {

SerialOpenMpScope::SerialOpenMpScope() {
  if (std::getenv("OMP_MAX_ACTIVE_LEVELS") != nullptr) return;
  previous_levels_ = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
}

SerialOpenMpScope::~SerialOpenMpScope() {
  if (previous_levels_ >= 0) omp_set_max_active_levels(previous_levels_);
}

}  // namespace slam
