#include "core/metrics/statistics.h"

#include <algorithm>
#include <cmath>

namespace slam {

ErrorStatistics ComputeErrorStatistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  const double n = static_cast<double>(errors.size());
  double sum = 0.0;
  double sse = 0.0;
  s.min = errors[0];
  s.max = errors[0];
  for (const double e : errors) {
    sum += e;
    sse += e * e;
    s.min = std::min(s.min, e);
    s.max = std::max(s.max, e);
  }
  s.mean = sum / n;
  s.sse = sse;
  s.rmse = std::sqrt(sse / n);
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);  // Population std (numpy's default ddof = 0).
  std::vector<double> sorted = errors;
  const size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + mid, sorted.end());
  const double upper = sorted[mid];
  if (sorted.size() % 2 == 1) {
    s.median = upper;
  } else {
    const double lower =
        *std::max_element(sorted.begin(), sorted.begin() + mid);
    s.median = 0.5 * (lower + upper);
  }
  return s;
}

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd r;
  if (values.empty()) return r;
  double sum = 0.0;
  for (double v : values) sum += v;
  r.mean = sum / static_cast<double>(values.size());
  if (values.size() < 2) return r;
  double sq = 0.0;
  for (double v : values) sq += (v - r.mean) * (v - r.mean);
  r.std = std::sqrt(sq / static_cast<double>(values.size() - 1));
  return r;
}

}  // namespace slam
