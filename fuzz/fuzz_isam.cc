// iSAM text graphs, from text in memory.
#include "datasets/isam_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return slam::fuzz::FuzzGraphReader(slam::ReadIsamFromText, "fuzz.txt", data,
                                     size);
}
