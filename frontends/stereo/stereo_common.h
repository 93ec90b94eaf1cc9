// Small helpers shared by the stereo frontend's files.
#ifndef SLAM_FRONTENDS_STEREO_STEREO_COMMON_H_
#define SLAM_FRONTENDS_STEREO_STEREO_COMMON_H_

#include <chrono>

#include <opencv2/core.hpp>
#include <opencv2/core/hal/hal.hpp>

namespace slam::stereo {

inline double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now() - start)
      .count();
}

// Hamming distance between row i of a and row j of b (ORB: 32-byte rows).
inline int Hamming(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  return cv::hal::normHamming(a.ptr<uchar>(i), b.ptr<uchar>(j), a.cols);
}

}  // namespace slam::stereo

#endif  // SLAM_FRONTENDS_STEREO_STEREO_COMMON_H_
