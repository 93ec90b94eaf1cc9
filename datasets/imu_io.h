// Reading and writing inertial datasets: IMU readings, position fixes and
// ground truth (pose, velocity, biases). Inside, stamps are int64
// nanoseconds and quaternions follow core/conventions.h (x, y, z, w).
//
// Formats:
//   GTSAM IMU + GPS CSV (GTSAM examples/Data/imuAndGPSdata.csv, read by
//   examples/ImuFactorsExample.cpp), comma separated, no header:
//     i,x,y,z,qx,qy,qz,qw,vx,vy,vz   first row: the initial state (the
//                                    example calls the axes N, E, D)
//     0,ax,ay,az,wx,wy,wz            IMU reading (body frame), m/s^2, rad/s
//     1,x,y,z,qx,qy,qz,qw            GPS fix: position; the rotation is
//                                    ground truth the example only prints
//   Trap in the shipped file: its "i" row is 0,0,0,0,0,0,0,0,0,1. Read in
//   the documented order that is q = (0, 0, 0, 0) and v = (0, 0, 1) m/s.
//   GTSAM turns the zero quaternion into the identity (Eigen's
//   toRotationMatrix does not normalize); this reader does the same (only
//   for an all-zero quaternion on the "i" row; elsewhere a zero quaternion is
//   an error). The velocity (0, 0, 1) is NOT consistent with the IMU and GPS
//   rows, which start at rest and stay at z = 0 (the row looks written as
//   p, v, q xyzw): estimators should not put a tight prior on it.
//   The file has no stamps: the example integrates every IMU row over a
//   fixed dt = 0.005 s. Here IMU row k (0-based) gets stamp k dt and covers
//   [k dt, (k + 1) dt); a GPS row gets the stamp n dt, n = number of IMU rows
//   before it (the end of the IMU data integrated so far). The example's
//   gravity is ZERO (PreintegrationParams::MakeSharedD(0.0)): the readings
//   of this synthetic file contain no gravity, so InertialData::gravity is
//   (0, 0, 0) after reading it. The example's noise: accel 0.0003924,
//   gyro 0.000205689024915 (continuous sigmas), accel bias random walk
//   0.004905, gyro bias random walk 0.000001454441043, GPS sigma 1 m.
//   The writer writes rows in stamp order (a fix before the IMU rows with
//   stamps >= its own), numbers in shortest round-trip digits.
//
//   EuRoC MAV folder (ASL format), readings in the sensor frame S = body:
//     mav0/imu0/data.csv    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y,
//                            w_RS_S_z,a_RS_S_x [m s^-2],a_RS_S_y,a_RS_S_z"
//                            (gyro FIRST, then accel); required.
//     mav0/state_groundtruth_estimate0/data.csv   optional, 17 columns:
//                            "#timestamp, p_RS_R_x,y,z, q_RS_w,x,y,z,
//                            v_RS_R_x,y,z, b_w_RS_S_x,y,z, b_a_RS_S_x,y,z"
//                            (quaternion w FIRST; bias gyro then accel).
//     mav0/leica0/data.csv  optional position fixes "#timestamp [ns],
//                            p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m]" (EuRoC
//                            stores its Leica prism positions so; this
//                            project's simulator writes its position fixes
//                            there too).
//   Stamps are integer nanoseconds and must increase strictly within a file.
//   Lines starting with '#' and blank lines are skipped; fields may carry
//   spaces around them. Gravity: (0, 0, -9.81) (world z up).
//   The writer creates the folders and writes each file atomically
//   (temporary file + rename), numbers in shortest round-trip digits.
//
// Errors: "PATH:LINE: problem" (wrong field count, bad number, unknown row
// type, non-increasing stamp, zero quaternion), or "PATH: problem".
// Readings no IMU produces are errors at reading time, with the value:
// an accelerometer component beyond kMaxImuAccel, a gyroscope component
// beyond kMaxImuGyro, a gap of more than kMaxImuGap between IMU readings
// (missing data the preintegration would bridge with one reading). A file
// without IMU readings is an error.
#ifndef SLAM_DATASETS_IMU_IO_H_
#define SLAM_DATASETS_IMU_IO_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/imu_preintegration.h"
#include "core/lie.h"
#include "core/sensors/inertial_data.h"

namespace slam {

// Plausibility bounds of IMU readings (consumer and tactical IMUs saturate
// at 16-200 g and 2000-5000 deg/s).
constexpr double kMaxImuAccel = 2000.0;    // m/s^2, about 200 g.
constexpr double kMaxImuGyro = 100.0;      // rad/s, about 5700 deg/s.
constexpr TimeNs kMaxImuGap = 1000000000;  // 1 s.

// The sample period of the GTSAM example file (ImuFactorsExample.cpp).
constexpr double kGtsamImuDt = 0.005;

bool ReadGtsamImuCsv(const std::string& path, double imu_dt, InertialData* data,
                     std::string* error);
// Needs has_initial_state and stamps that are multiples of imu_dt apart
// (only the order of the rows is written).
bool WriteGtsamImuCsv(const std::string& path, const InertialData& data,
                      std::string* error);

// `folder` is the dataset folder that holds mav0/ (or mav0 itself).
bool ReadEurocInertial(const std::string& folder, InertialData* data,
                       std::string* error);
// Writes mav0/imu0/data.csv, and state_groundtruth_estimate0/data.csv and
// leica0/data.csv when there is ground truth / there are fixes, under
// `folder`/mav0.
bool WriteEurocInertial(const std::string& folder, const InertialData& data,
                        std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_IMU_IO_H_
