// Inertial inputs: a GTSAM IMU + GPS CSV, or the files of an EuRoC folder
// (imu0, ground truth, leica0). The first byte picks the file.
#include <filesystem>
#include <string>

#include "datasets/imu_io.h"
#include "fuzz/fuzz_util.h"

namespace {

// A valid EuRoC IMU file for the cases that fuzz the other files.
constexpr char kImu[] =
    "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n"
    "1000000000,0,0,0,0,0,9.81\n"
    "1005000000,0,0,0,0,0,9.81\n"
    "1010000000,0,0,0,0,0,9.81\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int which = data[0] % 4;
  slam::InertialData inertial;
  std::string error;
  bool ok = false;
  if (which == 0) {
    const std::string path =
        slam::fuzz::WriteScratch("gtsam.csv", data + 1, size - 1);
    ok = slam::ReadGtsamImuCsv(path, slam::kGtsamImuDt, &inertial, &error);
  } else {
    const std::string root = slam::fuzz::ScratchDir() + "/euroc";
    std::error_code ec;
    std::filesystem::remove_all(root, ec);
    const char* files[] = {"mav0/imu0/data.csv",
                           "mav0/state_groundtruth_estimate0/data.csv",
                           "mav0/leica0/data.csv"};
    if (which != 1)
      slam::fuzz::WriteScratch(std::string("euroc/") + files[0], kImu);
    slam::fuzz::WriteScratch(std::string("euroc/") + files[which - 1], data + 1,
                             size - 1);
    ok = slam::ReadEurocInertial(root, &inertial, &error);
  }
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
