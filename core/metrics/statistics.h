// Summary statistics of error values.
//
// Statistics (evo PE.get_statistic): rmse = sqrt(mean(e^2)), mean, median
//   (numpy: mean of the two middle values for an even count), std
//   (population, ddof 0), min, max, sse = sum(e^2).
// MeanStd: mean and sample standard deviation (the relation-based error).
#ifndef SLAM_CORE_METRICS_STATISTICS_H_
#define SLAM_CORE_METRICS_STATISTICS_H_

#include <cstddef>
#include <vector>

namespace slam {

struct ErrorStatistics {
  size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;
};
// All zero for an empty vector.
ErrorStatistics ComputeErrorStatistics(const std::vector<double>& errors);

struct MeanStd {
  double mean = 0.0;
  double std = 0.0;  // Sample standard deviation (N - 1).
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_STATISTICS_H_
