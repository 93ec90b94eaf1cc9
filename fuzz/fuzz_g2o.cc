// g2o pose graphs (2D, 3D, landmarks), from text in memory.
#include "datasets/g2o_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return slam::fuzz::FuzzGraphReader(slam::ReadG2oFromText, "fuzz.g2o", data,
                                     size);
}
