#include "core/metrics/kitti_metric.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace slam {

bool ComputeKittiMetric(const std::vector<Pose3>& ref,
                        const std::vector<Pose3>& est, KittiMetric* metric,
                        std::string* error) {
  return ComputeKittiMetric(ToMatrixPoses(ref), ToMatrixPoses(est), metric,
                            error);
}

bool ComputeKittiMetric(const std::vector<MatrixPose>& ref,
                        const std::vector<MatrixPose>& est, KittiMetric* metric,
                        std::string* error) {
  *metric = KittiMetric();
  if (ref.size() != est.size()) {
    *error = "the KITTI metric needs matched trajectories of equal size";
    return false;
  }
  static const float kLengths[] = {100, 200, 300, 400, 500, 600, 700, 800};
  constexpr size_t kStepSize = 10;
  // Devkit trajectoryDistances: single precision.
  std::vector<float> dist(ref.size(), 0.0f);
  for (size_t i = 1; i < ref.size(); ++i) {
    const float dx = static_cast<float>(ref[i - 1].t.x() - ref[i].t.x());
    const float dy = static_cast<float>(ref[i - 1].t.y() - ref[i].t.y());
    const float dz = static_cast<float>(ref[i - 1].t.z() - ref[i].t.z());
    dist[i] = dist[i - 1] + std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  float t_sum = 0.0f;
  float r_sum = 0.0f;
  std::vector<double> len_t(8, 0.0);
  std::vector<double> len_r(8, 0.0);
  std::vector<size_t> len_n(8, 0);
  for (size_t first = 0; first < ref.size(); first += kStepSize) {
    for (size_t li = 0; li < 8; ++li) {
      const float len = kLengths[li];
      size_t last = ref.size();
      for (size_t i = first; i < dist.size(); ++i) {
        if (dist[i] > dist[first] + len) {
          last = i;
          break;
        }
      }
      if (last == ref.size()) continue;
      // The devkit inverts the 4x4 matrices as they are (Matrix::inv).
      const MatrixPose delta_gt = ref[first].Inverse() * ref[last];
      const MatrixPose delta_result = est[first].Inverse() * est[last];
      const MatrixPose pose_error = delta_result.Inverse() * delta_gt;
      const Eigen::Matrix3d& r = pose_error.r;
      // Devkit rotationError / translationError, in float as there.
      const float a = static_cast<float>(r(0, 0));
      const float b = static_cast<float>(r(1, 1));
      const float c = static_cast<float>(r(2, 2));
      const float d = static_cast<float>(0.5 * ((a + b + c) - 1.0));
      const float r_err = std::acos(std::max(std::min(d, 1.0f), -1.0f));
      const float tx = static_cast<float>(pose_error.t.x());
      const float ty = static_cast<float>(pose_error.t.y());
      const float tz = static_cast<float>(pose_error.t.z());
      const float t_err = std::sqrt(tx * tx + ty * ty + tz * tz);
      KittiSegmentError seg;
      seg.first_frame = first;
      seg.last_frame = last;
      seg.length = len;
      seg.t_err = t_err / len;
      seg.r_err = r_err / len;
      t_sum += t_err / len;
      r_sum += r_err / len;
      len_t[li] += seg.t_err;
      len_r[li] += seg.r_err;
      ++len_n[li];
      metric->segments.push_back(seg);
    }
  }
  metric->num_segments = metric->segments.size();
  if (metric->num_segments == 0) {
    metric->t_rel_percent = std::numeric_limits<double>::quiet_NaN();
    metric->r_rel_deg_per_100m = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  const float num = static_cast<float>(metric->num_segments);
  metric->t_rel_percent = 100.0 * static_cast<double>(t_sum / num);
  metric->r_rel_deg_per_100m =
      static_cast<double>(r_sum / num) * 180.0 / M_PI * 100.0;
  for (size_t li = 0; li < 8; ++li) {
    if (len_n[li] == 0) continue;
    KittiLengthSummary s;
    s.length = kLengths[li];
    s.count = len_n[li];
    s.t_rel_percent = 100.0 * len_t[li] / len_n[li];
    s.r_rel_deg_per_100m = len_r[li] / len_n[li] * 180.0 / M_PI * 100.0;
    metric->by_length.push_back(s);
  }
  return true;
}

}  // namespace slam
