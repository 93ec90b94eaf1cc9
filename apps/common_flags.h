// Flags shared by several subcommands (defined once in common_flags.cc).
#ifndef SLAM_APPS_COMMON_FLAGS_H_
#define SLAM_APPS_COMMON_FLAGS_H_

#include <gflags/gflags.h>

DECLARE_string(config);
DECLARE_bool(dump_config);
DECLARE_string(report);
DECLARE_string(plot);
DECLARE_string(gt);

#endif  // SLAM_APPS_COMMON_FLAGS_H_
