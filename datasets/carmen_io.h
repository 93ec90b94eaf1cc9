// Reading and writing CARMEN robot logs (.clf / .log, plain or compressed with
// bzip2; the compression is detected by the "BZh" magic, not by the name, and
// the data is decompressed piece by piece while it is parsed).
//
// Lines (fields separated by white space; each message line ends with
// "ipc_timestamp ipc_hostname logger_timestamp", the stamps in seconds):
//   PARAM name value ...
//   ODOM x y theta tv rv accel ipc_ts host logger_ts
//   FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta ipc_ts host
//          logger_ts                                           (RLASER alike)
//   ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy
//          remission_mode n r_1 .. r_n n_rem rem_1 .. rem_n_rem laser_x
//          laser_y laser_theta robot_x robot_y robot_theta tv rv
//          forward_safety_dist side_safety_dist turn_axis ipc_ts host
//          logger_ts
// Angles are in radians, distances in metres.
//
// Conventions of what is read:
// - LaserScan::stamp and OdometryReading::stamp are the ipc_timestamp, read
//   exactly from the decimal text (the stamps .relations files refer to).
// - LaserScan::odom is the robot's odometry pose of the line (FLASER/RLASER:
//   odom_x odom_y odom_theta; ROBOTLASER1: robot_x robot_y robot_theta);
//   LaserScan::logged_pose is the other pose of the line (FLASER/RLASER:
//   x y theta, the corrected robot pose; ROBOTLASER1: the laser pose).
// - LaserScan::laser_offset is the pose of the laser in the robot frame.
//   FLASER: (robot_frontlaser_offset, 0, 0); RLASER: the rear laser looks
//   backwards, (-robot_rearlaser_offset, 0, pi); the offsets are the PARAM
//   values known when the line is read (0 when absent). ROBOTLASER1:
//   robot_pose^-1 * laser_pose.
// - Beam i has the angle angle_min + i * angle_increment in the laser frame
//   (x forward, y left). ROBOTLASER1 gives start_angle, angular_res and
//   max_range. FLASER/RLASER do not: as CARMEN's own reader
//   (carmen_laser_guess_angle_increment) and GMapping's carmenconfiguration
//   do, the first beam is at -fov/2 with fov = 180 deg and the increment is
//   1 deg for 180 or 181 readings, 0.5 deg for 360 or 361, 0.25 deg for 400
//   or 401 and fov / (n - 1) otherwise. PARAM laser_front_laser_fov (deg;
//   laser_rear_laser_fov for RLASER) moves the first beam to -fov/2, PARAM
//   laser_front_laser_resolution (deg) sets the increment, PARAM
//   robot_front_laser_max (robot_rear_laser_max) the maximum range, else
//   CarmenReadOptions::default_max_range. Readings at or beyond max_range
//   mean "no return".
// - Other tags (SYNC, TRUEPOS, NMEA-GGA, ...) are skipped with one warning
//   per tag giving the number of lines; '#' comment lines are skipped
//   silently; lasers not selected in the options are skipped silently.
//
// Errors: "PATH:LINE: problem" for a wrong field count, a bad, non-finite or
// negative number, a pose coordinate beyond 1e7 m; "PATH: problem" for an
// unreadable or corrupt file. Nothing is returned on error (the log is left
// empty).
#ifndef SLAM_DATASETS_CARMEN_IO_H_
#define SLAM_DATASETS_CARMEN_IO_H_

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/sensors/laser_data.h"

namespace slam {

// Called now and then while reading with the fraction done, in [0, 1].
using ProgressCallback = std::function<void(double fraction)>;

struct CarmenLog {
  // In file order, also where stamps go backwards (real logs have that:
  // intel.clf, 631 of 13631 scans): the order is the order of acquisition.
  std::vector<LaserScan> scans;
  // Scans whose stamp is not after the previous scan's (of any selected
  // laser); a warning says how many. Writers of stamped outputs must sort.
  int64_t scans_out_of_order = 0;
  std::vector<OdometryReading> odometry;
  std::map<std::string, std::string> params;  // Last value of each PARAM.
  std::vector<std::string> warnings;
};

struct CarmenReadOptions {
  bool front_laser = true;  // FLASER lines.
  bool rear_laser = false;  // RLASER lines.
  bool robot_laser = true;  // ROBOTLASER1 lines.
  // FLASER/RLASER maximum range without a robot_*_laser_max PARAM (the SICK
  // LMS reports 81.91 m for "no return").
  double default_max_range = 81.9;
  // Bounds on what a log may make the reader hold: the text of the log
  // (after bzip2 decompression, which is streamed: a 13 KB bomb that
  // decompresses to 12 GB is stopped here) and one line. The largest public
  // CARMEN logs are a few hundred MB; a ROBOTLASER1 line of 2^20 readings
  // is about 10 MB.
  uint64_t max_log_bytes = uint64_t{2} << 30;  // 2 GiB.
  size_t max_line_bytes = size_t{64} << 20;    // 64 MiB.
};

bool ReadCarmenLog(const std::string& path, const CarmenReadOptions& options,
                   CarmenLog* log, std::string* error,
                   ProgressCallback progress = nullptr);

// Parses log text already in memory (name is used in error messages).
bool ParseCarmenLog(const std::string& name, const std::string& text,
                    const CarmenReadOptions& options, CarmenLog* log,
                    std::string* error, ProgressCallback progress = nullptr);

// Writes a plain-text log: the PARAM lines (name order), then the ODOM and
// laser lines merged by stamp (ODOM first on equal stamps; lasers of one tag
// keep their order). FLASER/RLASER scans are written with their ranges and
// poses only (their angles come back from the n-based rule and the PARAMs);
// ROBOTLASER1 with everything LaserScan holds (remissions empty, velocities
// and safety fields 0). Numbers are written so that they read back bit for
// bit; the host field is "nohost", logger_timestamp = ipc_timestamp.
// Through a temporary file and a rename (datasets/atomic_file.h).
bool WriteCarmenLog(const std::string& path, const CarmenLog& log,
                    std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_CARMEN_IO_H_
