// printf-style formatting of one number, for the messages of the metrics
// (internal to core/metrics/).
#ifndef SLAM_CORE_METRICS_FORMAT_H_
#define SLAM_CORE_METRICS_FORMAT_H_

#include <cstdio>
#include <string>

namespace slam {

namespace metrics_internal {

inline std::string Format(const char* fmt, double a) {
  char buf[128];
  std::snprintf(buf, sizeof(buf), fmt, a);
  return buf;
}

}  // namespace metrics_internal

}  // namespace slam

#endif  // SLAM_CORE_METRICS_FORMAT_H_
