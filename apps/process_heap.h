// Heap policy of the slam process.
//
// The solvers allocate tens of megabytes (Jacobians, normal equations, the
// Cholesky factor, the initializers' triplets) and touch every page once.
// On the machine class the benchmarks run on (a VM), a 4 KiB page fault
// costs about 6 us, and faults were 15-25 % of the wall time of the
// pose-graph benchmarks (parking-garage: 8,600 faults in 0.31 s). Backing
// the heap with transparent huge pages (2 MiB per fault) removes almost all
// of them: parking-garage 0.31 -> 0.22 s, city10000 0.51 -> 0.38 s,
// torus3D 1.25 -> 1.03 s, intel 64 -> 50 ms (perf stat, 5 runs each).
//
// ConfigureProcessHeap() does, once, at the start of main():
//  - all threads allocate from the main arena (no per-thread mmap'd heaps
//    that the next two points would not cover);
//  - blocks up to 32 MiB (glibc's largest mmap threshold) come from the
//    brk heap, and freed memory is kept rather than trimmed, so buffers
//    freed and reallocated every iteration are not faulted in again;
//  - when the kernel offers transparent huge pages ("always" or
//    "madvise"), the heap is grown once by 1 GiB of address space (no memory
//    is committed until touched) and that range is marked MADV_HUGEPAGE.
//    This is what glibc's own tunable glibc.malloc.hugetlb=1 does, which can
//    only be set from the environment before the process starts.
// Everything here is an optimization: when a call fails the process runs
// with glibc's defaults.
#ifndef SLAM_APPS_PROCESS_HEAP_H_
#define SLAM_APPS_PROCESS_HEAP_H_

namespace slam {

void ConfigureProcessHeap();

}  // namespace slam

#endif  // SLAM_APPS_PROCESS_HEAP_H_
