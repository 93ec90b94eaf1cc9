// printf-style formatting of one number into a std::string, for the tables
// and plot labels of the evaluation.
#ifndef SLAM_APPS_FORMAT_H_
#define SLAM_APPS_FORMAT_H_

#include <cstdio>
#include <string>

namespace slam {

inline std::string Fmt(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

}  // namespace slam

#endif  // SLAM_APPS_FORMAT_H_
