// GTSAM stereo VO files: the input is the factor file, or (first byte) the
// calibration or the camera poses beside valid other files.
#include <string>

#include "datasets/stereo_vo_io.h"
#include "fuzz/fuzz_util.h"

namespace {

constexpr char kCalibration[] = "700 700 0 600 180 0.5\n";
constexpr char kPoses[] =
    "1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
    "2 1 0 0 0.5 0 1 0 0 0 0 1 0 0 0 0 1\n";
constexpr char kFactors[] =
    "1 1 650 630 200 1 0.5 10\n"
    "2 1 615 595 200 0.5 0.5 10\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int which = data[0] % 3;
  std::string paths[3] = {
      slam::fuzz::WriteScratch("factors.txt", kFactors),
      slam::fuzz::WriteScratch("calibration.txt", kCalibration),
      slam::fuzz::WriteScratch("poses.txt", kPoses)};
  const char* names[3] = {"factors.txt", "calibration.txt", "poses.txt"};
  paths[which] = slam::fuzz::WriteScratch(names[which], data + 1, size - 1);
  slam::Graph graph;
  slam::StereoVoReport report;
  std::string error;
  const bool ok =
      slam::ReadStereoVo(paths[0], paths[1], paths[2], &graph, &report, &error);
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
