// Relation files ("t1 t2 x y z roll pitch yaw").
#include <string>
#include <vector>

#include "datasets/relations_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path =
      slam::fuzz::WriteScratch("fuzz.relations", data, size);
  std::vector<slam::PoseRelation> relations;
  std::string error;
  const bool ok = slam::ReadRelations(path, &relations, &error);
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
