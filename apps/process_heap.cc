#include "apps/process_heap.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

namespace slam {
namespace {

constexpr int kLargestMmapThreshold = 32 << 20;  // glibc: HEAP_MAX_SIZE / 2.
constexpr int kHugeReserve = 1 << 30;
constexpr int kLaterTopPad = 64 << 20;
constexpr uintptr_t kHugePage = 2 << 20;

bool KernelOffersHugePages() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  if (!std::getline(in, modes)) return false;
  return modes.find("[always]") != std::string::npos ||
         modes.find("[madvise]") != std::string::npos;
}

}  // namespace

void ConfigureProcessHeap() {
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, kLargestMmapThreshold);
  mallopt(M_TRIM_THRESHOLD, 0x7fffffff);
  if (!KernelOffersHugePages()) {
    mallopt(M_TOP_PAD, kLaterTopPad);
    return;
  }
  // Grow the heap once: a block larger than the free top of the heap makes
  // malloc extend it by the block plus M_TOP_PAD; freeing the block leaves
  // all of it as free top (nothing is trimmed).
  mallopt(M_TOP_PAD, kHugeReserve);
  const auto before = reinterpret_cast<uintptr_t>(sbrk(0));
  void* probe = std::malloc(kLargestMmapThreshold / 2);
  // Keep the compiler from eliding the unused malloc/free pair.
  asm volatile("" : : "g"(probe) : "memory");
  std::free(probe);
  const auto after = reinterpret_cast<uintptr_t>(sbrk(0));
  mallopt(M_TOP_PAD, kLaterTopPad);
  const uintptr_t begin = (before + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t end = after & ~(kHugePage - 1);
  if (end > begin) {
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  }
}

}  // namespace slam
