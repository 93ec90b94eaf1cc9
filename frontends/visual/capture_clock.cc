#include "frontends/visual/capture_clock.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace slam {
namespace {

// The pose a fraction f of the way from a to b (f outside [0, 1]:
// extrapolated along the same motion): linear in position, the rotation
// a * Exp(f Log(a^-1 b)) (slerp for f in [0, 1]).
Pose3 Blend(const Pose3& a, const Pose3& b, double f) {
  const Eigen::AngleAxisd delta(a.q.conjugate() * b.q);
  const Eigen::Quaterniond step(
      Eigen::AngleAxisd(f * delta.angle(), delta.axis()));
  return Pose3(a.t + f * (b.t - a.t), a.q * step);
}

}  // namespace

CaptureClock FitCaptureClock(const std::vector<TimeNs>& stamps) {
  CaptureClock clock;
  clock.capture = stamps;
  const size_t n = stamps.size();
  if (n < 3) return clock;
  std::vector<double> steps;  // s.
  for (size_t i = 1; i < n; ++i) {
    if (stamps[i] <= stamps[i - 1]) return clock;
    steps.push_back(NsToSeconds(stamps[i] - stamps[i - 1]));
  }
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                   sorted.end());
  double period = sorted[sorted.size() / 2];
  std::vector<double> count(n, 0.0), t(n, 0.0);
  double a = 0.0;
  // Counts from the median interval, then once more from the fitted period.
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t i = 1; i < n; ++i) {
      count[i] =
          count[i - 1] + std::max(1.0, std::round(steps[i - 1] / period));
      t[i] = NsToSeconds(stamps[i] - stamps[0]);
    }
    double sk = 0, st = 0, skk = 0, skt = 0;
    for (size_t i = 0; i < n; ++i) {
      sk += count[i], st += t[i], skk += count[i] * count[i];
      skt += count[i] * t[i];
    }
    const double det = n * skk - sk * sk;
    if (!(det > 0)) return clock;
    period = (n * skt - sk * st) / det;
    a = (st - period * sk) / n;
    if (!(period > 0)) return clock;
  }
  double min_residual = INFINITY, sse = 0.0, max_abs = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double r = t[i] - (a + period * count[i]);
    min_residual = std::min(min_residual, r);
    sse += r * r;
    max_abs = std::max(max_abs, std::abs(r));
  }
  if (!(max_abs < 0.25 * period)) return clock;  // Not a fixed rate.
  clock.fixed_rate = true;
  clock.period = period;
  clock.jitter_rms = std::sqrt(sse / n);
  for (size_t i = 0; i < n; ++i) {
    const double capture = a + period * count[i] + min_residual;
    clock.capture[i] = stamps[0] + SecondsToNs(capture);
    clock.latency_max =
        std::max(clock.latency_max, NsToSeconds(stamps[i] - clock.capture[i]));
  }
  return clock;
}

Trajectory PosesAtStamps(const Trajectory& at_capture,
                         const std::vector<TimeNs>& capture) {
  const size_t n = at_capture.size();
  if (n < 2 || capture.size() != n) return at_capture;
  Trajectory out = at_capture;
  for (size_t i = 0; i < n; ++i) {
    const TimeNs stamp = at_capture[i].stamp;
    // The capture interval [j, j + 1] holding the stamp (the first or last
    // one outside the captures' span).
    size_t j = static_cast<size_t>(
        std::upper_bound(capture.begin(), capture.end(), stamp) -
        capture.begin());
    j = std::min(std::max<size_t>(j, 1), n - 1) - 1;
    const double span = static_cast<double>(capture[j + 1] - capture[j]);
    if (!(span > 0)) continue;
    const double f = static_cast<double>(stamp - capture[j]) / span;
    out[i].pose = Blend(at_capture[j].pose, at_capture[j + 1].pose, f);
  }
  return out;
}

}  // namespace slam
