// TORO / HOG-Man graphs, from text in memory.
#include "datasets/toro_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return slam::fuzz::FuzzGraphReader(slam::ReadToroFromText, "fuzz.graph", data,
                                     size);
}
