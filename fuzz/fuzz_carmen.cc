// CARMEN logs, plain or bzip2-compressed (through the file reader, which
// detects the compression by content).
#include <string>

#include "datasets/carmen_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  slam::CarmenReadOptions options;
  if (size > 0) options.rear_laser = (data[0] & 1) != 0;
  const std::string path = slam::fuzz::WriteScratch("fuzz.clf", data, size);
  slam::CarmenLog log;
  std::string error;
  const bool ok = slam::ReadCarmenLog(path, options, &log, &error);
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
