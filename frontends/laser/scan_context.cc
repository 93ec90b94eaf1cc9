#include "frontends/laser/scan_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slam {

ScanContext MakeScanContext(const Points2& points,
                            const ScanContextOptions& options) {
  ScanContext sc;
  sc.rings = std::max(1, options.rings);
  sc.sectors = std::max(1, options.sectors);
  sc.cells.assign(static_cast<size_t>(sc.rings) * sc.sectors, 0.0f);
  const int harmonics =
      std::max(0, std::min(options.key_harmonics, sc.sectors / 2));
  sc.ring_key.assign(static_cast<size_t>(sc.rings) * (harmonics + 1), 0.0f);
  for (const Eigen::Vector2d& p : points) {
    const double r = p.norm();
    if (!(r < options.max_range)) continue;
    const int ring = std::min(
        sc.rings - 1, static_cast<int>(r / options.max_range * sc.rings));
    double phi = std::atan2(p.y(), p.x());
    if (phi < 0) phi += 2.0 * M_PI;
    const int sector = std::min(
        sc.sectors - 1, static_cast<int>(phi / (2.0 * M_PI) * sc.sectors));
    sc.cells[static_cast<size_t>(ring) * sc.sectors + sector] = 1.0f;
  }
  for (int i = 0; i < sc.rings; ++i) {
    const float* row = &sc.cells[static_cast<size_t>(i) * sc.sectors];
    float* key = &sc.ring_key[static_cast<size_t>(i) * (harmonics + 1)];
    for (int s = 0; s < sc.sectors; ++s) key[0] += row[s];
    key[0] /= sc.sectors;
    for (int h = 1; h <= harmonics; ++h) {
      double re = 0.0, im = 0.0;
      for (int s = 0; s < sc.sectors; ++s) {
        if (row[s] == 0.0f) continue;
        const double phase = 2.0 * M_PI * h * s / sc.sectors;
        re += std::cos(phase);
        im += std::sin(phase);
      }
      key[h] = static_cast<float>(std::hypot(re, im) / sc.sectors);
    }
  }
  return sc;
}

double RingKeyDistance(const ScanContext& a, const ScanContext& b) {
  if (a.ring_key.size() != b.ring_key.size()) {
    return std::numeric_limits<double>::infinity();
  }
  double d = 0.0;
  for (size_t i = 0; i < a.ring_key.size(); ++i) {
    const double e = a.ring_key[i] - b.ring_key[i];
    d += e * e;
  }
  return d;
}

double ScanContextDistance(const ScanContext& a, const ScanContext& b,
                           double* rotation) {
  *rotation = 0.0;
  if (a.empty() || a.rings != b.rings || a.sectors != b.sectors) return 1.0;
  const int n = a.sectors, m = a.rings;
  // Column norms (the cells are 0/1: the norm is the root of the count).
  std::vector<double> na(n, 0.0), nb(n, 0.0);
  for (int s = 0; s < n; ++s) {
    for (int i = 0; i < m; ++i) {
      na[s] += a.cells[static_cast<size_t>(i) * n + s];
      nb[s] += b.cells[static_cast<size_t>(i) * n + s];
    }
    na[s] = std::sqrt(na[s]);
    nb[s] = std::sqrt(nb[s]);
  }
  double best = std::numeric_limits<double>::infinity();
  int best_shift = 0;
  for (int shift = 0; shift < n; ++shift) {
    double sum = 0.0;
    int used = 0;
    for (int s = 0; s < n; ++s) {
      const int t = (s + shift) % n;
      if (na[s] == 0.0 && nb[t] == 0.0) continue;
      ++used;
      if (na[s] == 0.0 || nb[t] == 0.0) {
        sum += 1.0;
        continue;
      }
      double dot = 0.0;
      for (int i = 0; i < m; ++i) {
        dot += a.cells[static_cast<size_t>(i) * n + s] *
               b.cells[static_cast<size_t>(i) * n + t];
      }
      sum += 1.0 - dot / (na[s] * nb[t]);
    }
    const double d = used > 0 ? sum / used : 1.0;
    if (d < best) {
      best = d;
      best_shift = shift;
    }
  }
  *rotation = NormalizeAngle(2.0 * M_PI * best_shift / n);
  return best;
}

}  // namespace slam
