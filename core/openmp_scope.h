// SerialOpenMpScope: run the libraries' OpenMP regions on one thread while
// a solve is under way.
//
// Why: Debian's CHOLMOD (SuiteSparse 5.12) opens an OpenMP parallel region
// with a compile-time team of 4 threads for every supernode it factorizes
// (clearing a few hundred entries at a time) and ignores OMP_NUM_THREADS,
// because the thread count is a constant in the num_threads clause. On a
// 2-core machine the hand-offs cost far more than the work: sphere2500 made
// 75,000 futex calls and spent 0.25 s in the kernel for 0.4 s of arithmetic.
// Setting the OpenMP "max active levels" to 0 makes every parallel region
// inactive (one thread), which the clause cannot override. Threading of the
// solve itself stays with Ceres (Solver::Options::num_threads), which uses
// its own thread pool, not OpenMP.
//
// The scope restores the previous setting when it ends, so a caller that
// wants OpenMP elsewhere keeps it; OMP_MAX_ACTIVE_LEVELS set in the
// environment is honoured (the scope then changes nothing).
#ifndef SLAM_CORE_OPENMP_SCOPE_H_
#define SLAM_CORE_OPENMP_SCOPE_H_

namespace slam {

class SerialOpenMpScope {
 public:
  SerialOpenMpScope();
  ~SerialOpenMpScope();
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  int previous_levels_ = -1;  // -1: nothing changed, nothing to restore.
};

}  // namespace slam

#endif  // SLAM_CORE_OPENMP_SCOPE_H_
