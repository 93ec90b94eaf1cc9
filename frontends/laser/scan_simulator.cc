#include "frontends/laser/scan_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slam {

std::vector<Wall> RectangleWalls(double x0, double y0, double x1, double y1) {
  const Eigen::Vector2d a(x0, y0), b(x1, y0), c(x1, y1), d(x0, y1);
  return {{a, b}, {b, c}, {c, d}, {d, a}};
}

std::vector<float> SimulateScan(const std::vector<Wall>& walls,
                                const Pose2& laser_pose,
                                const ScanGeometry& geometry, double sigma,
                                std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<float> ranges(geometry.num_beams);
  for (int i = 0; i < geometry.num_beams; ++i) {
    const double angle =
        laser_pose.theta + geometry.angle_min + i * geometry.angle_increment;
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    double best = std::numeric_limits<double>::infinity();
    for (const Wall& w : walls) {
      // Solve o + s dir = a + u (b - a), s > 0, u in [0, 1].
      const Eigen::Vector2d e = w.b - w.a;
      const double den = dir.x() * (-e.y()) - dir.y() * (-e.x());
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d rhs = w.a - laser_pose.t;
      const double s = (rhs.x() * (-e.y()) - rhs.y() * (-e.x())) / den;
      const double u = (dir.x() * rhs.y() - dir.y() * rhs.x()) / den;
      if (s > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, s);
    }
    double r = best;
    if (!(r < geometry.max_range)) {
      r = geometry.max_range;
    } else if (rng != nullptr && sigma > 0) {
      r = std::min(geometry.max_range - 1e-3, std::max(0.0, r + noise(*rng)));
    }
    ranges[i] = static_cast<float>(r);
  }
  return ranges;
}

std::vector<Pose2> ApplyOdometryFault(const std::vector<Pose2>& odometry,
                                      const OdometryFault& fault) {
  std::vector<Pose2> out = odometry;
  const int n = static_cast<int>(odometry.size());
  if (fault.first < 1 || fault.first >= n) return out;
  for (int i = fault.first; i < n; ++i) {
    Pose2 step = odometry[i - 1].Inverse() * odometry[i];
    const bool inside = i < fault.first + std::max(1, fault.length);
    switch (fault.kind) {
      case OdometryFault::kFreeze:
        out[i] = inside
                     ? out[i - 1]
                     : out[fault.first - 1] *
                           (odometry[fault.first - 1].Inverse() * odometry[i]);
        continue;
      case OdometryFault::kJump:
        if (i == fault.first) step = step * fault.jump;
        break;
      case OdometryFault::kRotationSlip:
        if (inside) step.theta *= fault.rotation_scale;
        break;
    }
    out[i] = out[i - 1] * step;
  }
  return out;
}

}  // namespace slam
