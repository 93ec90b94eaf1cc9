// Trajectory files: TUM, KITTI (with a times file), EuRoC CSV, g2o poses and
// format detection. The first byte picks the reader.
#include <string>

#include "datasets/trajectory_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int which = data[0] % 6;
  const std::string path =
      slam::fuzz::WriteScratch("trajectory", data + 1, size - 1);
  slam::TrajectoryReadOptions options;
  switch (which) {
    case 0:
      options.format = slam::TrajectoryFormat::kAuto;
      break;
    case 1:
      options.format = slam::TrajectoryFormat::kTum;
      break;
    case 2:
      options.format = slam::TrajectoryFormat::kKitti;
      break;
    case 3:
      options.format = slam::TrajectoryFormat::kEuroc;
      break;
    case 4:
      options.format = slam::TrajectoryFormat::kG2o;
      break;
    case 5:  // The input as KITTI times beside a fixed two-pose file.
      options.format = slam::TrajectoryFormat::kKitti;
      options.kitti_times_path = path;
      break;
  }
  std::string read_path = path;
  if (which == 5) {
    read_path = slam::fuzz::WriteScratch(
        "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  }
  slam::TrajectoryData trajectory;
  std::string error;
  const bool ok = slam::ReadTrajectory(read_path, options, &trajectory, &error);
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
