#include "core/metrics/evaluation.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace slam {
namespace {

std::string Format(const char* fmt, double a) {
  char buf[128];
  std::snprintf(buf, sizeof(buf), fmt, a);
  return buf;
}

std::string Seconds(TimeNs ns) { return Format("%.6f", NsToSeconds(ns)); }

// b - a in seconds, without int64 overflow for stamps of opposite signs.
double SecondsBetween(TimeNs a, TimeNs b) {
  return static_cast<double>(static_cast<__int128>(b) - a) * 1e-9;
}

// Relative pose a^-1 b (evo's relative_se3: the transpose as inverse).
MatrixPose Between(const MatrixPose& a, const MatrixPose& b) {
  return a.TransposeInverse() * b;
}

}  // namespace

// ------------------------------------------------------------------- poses

MatrixPose::MatrixPose(const Pose3& pose) : t(pose.t) {
  // transformations.quaternion_matrix: q *= sqrt(2 / |q|^2), then the
  // entries of the outer product q q^T (q = w, x, y, z).
  const Eigen::Quaterniond& q = pose.q;
  double v[4] = {q.w(), q.x(), q.y(), q.z()};
  const double n = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3];
  if (n < std::numeric_limits<double>::epsilon() * 4.0) return;
  const double f = std::sqrt(2.0 / n);
  for (double& x : v) x *= f;
  auto o = [&](int i, int j) { return v[i] * v[j]; };
  r << 1.0 - o(2, 2) - o(3, 3), o(1, 2) - o(3, 0), o(1, 3) + o(2, 0),
      o(1, 2) + o(3, 0), 1.0 - o(1, 1) - o(3, 3), o(2, 3) - o(1, 0),
      o(1, 3) - o(2, 0), o(2, 3) + o(1, 0), 1.0 - o(1, 1) - o(2, 2);
}

std::vector<MatrixPose> ToMatrixPoses(const std::vector<Pose3>& poses) {
  std::vector<MatrixPose> out;
  out.reserve(poses.size());
  for (const Pose3& p : poses) out.emplace_back(p);
  return out;
}

double NearestSeconds(TimeNs ns) {
  // Up to 2^53 the integer is exact in a double and IEEE division rounds
  // correctly.
  constexpr TimeNs kExact = TimeNs{1} << 53;
  if (ns > -kExact && ns < kExact) return static_cast<double>(ns) / 1e9;
  // Otherwise the exact decimal text, then its correctly rounded double.
  char buf[40];
  const bool negative = ns < 0;
  const unsigned long long a = negative
                                   ? 0ULL - static_cast<unsigned long long>(ns)
                                   : static_cast<unsigned long long>(ns);
  const int len =
      std::snprintf(buf, sizeof(buf), "%s%llu.%09llu", negative ? "-" : "",
                    a / 1000000000ULL, a % 1000000000ULL);
  double value = 0.0;
  std::from_chars(buf, buf + len, value);
  return value;
}

EvalTrajectory ToEvalTrajectory(const Trajectory& trajectory) {
  EvalTrajectory out;
  out.stamps.reserve(trajectory.size());
  out.seconds.reserve(trajectory.size());
  out.poses.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) {
    out.stamps.push_back(p.stamp);
    out.seconds.push_back(NearestSeconds(p.stamp));
    out.poses.emplace_back(p.pose);
  }
  return out;
}

// ---------------------------------------------------------------- statistics

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

// --------------------------------------------------------------- association

bool CheckAssociationOptions(const AssociationOptions& options,
                             std::string* error) {
  if (!(options.t_max_diff >= 0.0)) {
    *error = "t_max_diff must be >= 0 (got " +
             Format("%g", options.t_max_diff) + ")";
    return false;
  }
  if (!std::isfinite(options.t_offset)) {
    *error = "t_offset must be a finite number of seconds (got " +
             Format("%g", options.t_offset) + ")";
    return false;
  }
  return true;
}

Association AssociateByTimestamp(const EvalTrajectory& ref,
                                 const EvalTrajectory& est,
                                 const AssociationOptions& options) {
  Association result;
  result.by_index = false;
  // As evo: iterate over the trajectory with fewer poses (the estimate when
  // both have as many) and look up the nearest stamp of the other, whose
  // stamps carry the offset (+offset for the estimate, -offset for the
  // reference), all in float64 seconds. evo takes numpy's argmin of
  // |stamp - t| over the stamps in file order: the lowest index among the
  // closest. Here the stamps are sorted (stably, so equal stamps keep their
  // file order) and searched; files need not be sorted.
  const bool est_longer = est.size() > ref.size();
  const std::vector<double>& shorter = est_longer ? ref.seconds : est.seconds;
  const std::vector<double>& longer_raw =
      est_longer ? est.seconds : ref.seconds;
  result.max_pairs = shorter.size();
  const double offset = est_longer ? options.t_offset : -options.t_offset;
  const size_t n = longer_raw.size();
  std::vector<double> shifted(n);
  for (size_t j = 0; j < n; ++j) shifted[j] = longer_raw[j] + offset;
  std::vector<size_t> order(n);  // File indices by stamp.
  for (size_t j = 0; j < n; ++j) order[j] = j;
  if (!std::is_sorted(shifted.begin(), shifted.end())) {
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return shifted[a] < shifted[b];
    });
  }
  std::vector<double> value(n);
  for (size_t j = 0; j < n; ++j) value[j] = shifted[order[j]];
  // run_end[p]: the first position after the run of stamps equal to
  // value[p]; the first of a run has the run's lowest file index.
  std::vector<size_t> run_end(n);
  for (size_t j = n; j-- > 0;) {
    run_end[j] = j + 1 < n && value[j + 1] == value[j] ? run_end[j + 1] : j + 1;
  }

  std::vector<size_t> short_ids;
  std::vector<size_t> long_ids;
  std::vector<double> abs_diffs;
  for (size_t s = 0; s < shorter.size(); ++s) {
    const double t = shorter[s];
    // |value[p] - t| does not increase up to k (the first p with value[p]
    // >= t) and does not decrease from k on. Candidates: every run whose
    // difference equals the smallest on its side (more than one run only
    // when rounding maps different stamps to one difference).
    const size_t k = static_cast<size_t>(
        std::lower_bound(value.begin(), value.end(), t) - value.begin());
    size_t best = n;  // File index.
    double best_diff = std::numeric_limits<double>::infinity();
    auto consider = [&](size_t file_index, double diff) {
      if (diff < best_diff || (diff == best_diff && file_index < best)) {
        best = file_index;
        best_diff = diff;
      }
    };
    if (k > 0) {
      const double d = std::fabs(value[k - 1] - t);
      size_t lo = 0, hi = k - 1;  // First p in [lo, hi] with diff <= d.
      while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (std::fabs(value[mid] - t) <= d) {
          hi = mid;
        } else {
          lo = mid + 1;
        }
      }
      for (size_t p = lo; p < k; p = run_end[p]) consider(order[p], d);
    }
    if (k < n) {
      const double d = std::fabs(value[k] - t);
      for (size_t p = k; p < n && std::fabs(value[p] - t) == d;
           p = run_end[p]) {
        consider(order[p], d);
      }
    }
    if (best < n && best_diff <= options.t_max_diff) {
      short_ids.push_back(s);
      long_ids.push_back(best);
      abs_diffs.push_back(best_diff);
    }
  }
  // A pose of the longer trajectory in several pairs: evo keeps them all;
  // unique_pairs keeps the pair with the smallest difference (the first on
  // a tie).
  std::vector<size_t> keep;
  std::vector<size_t> best_pair(n, n);  // Per long index: its kept pair.
  for (size_t i = 0; i < long_ids.size(); ++i) {
    size_t& b = best_pair[long_ids[i]];
    if (b == n) {
      b = i;
      continue;
    }
    if (options.unique_pairs) {
      if (abs_diffs[i] < abs_diffs[b]) b = i;
      ++result.dropped_duplicates;
    } else {
      ++result.reused_poses;
    }
  }
  for (size_t i = 0; i < long_ids.size(); ++i) {
    if (options.unique_pairs && best_pair[long_ids[i]] != i) continue;
    keep.push_back(i);
  }
  for (const size_t k : keep) {
    const size_t ri = est_longer ? short_ids[k] : long_ids[k];
    const size_t ei = est_longer ? long_ids[k] : short_ids[k];
    result.ref_indices.push_back(ri);
    result.est_indices.push_back(ei);
    result.max_abs_dt = std::max(result.max_abs_dt, abs_diffs[k]);
  }
  return result;
}

Association AssociateByTimestamp(const Trajectory& ref, const Trajectory& est,
                                 const AssociationOptions& options) {
  return AssociateByTimestamp(ToEvalTrajectory(ref), ToEvalTrajectory(est),
                              options);
}

namespace {

bool AssociateBySize(size_t ref_size, size_t est_size, Association* association,
                     std::string* error) {
  if (ref_size != est_size) {
    *error =
        "association by index needs as many poses in both trajectories "
        "(reference " +
        std::to_string(ref_size) + ", estimate " + std::to_string(est_size) +
        "); give stamps (e.g. a KITTI times file) to associate by time";
    return false;
  }
  *association = Association();
  association->by_index = true;
  association->max_pairs = ref_size;
  for (size_t i = 0; i < ref_size; ++i) {
    association->ref_indices.push_back(i);
    association->est_indices.push_back(i);
  }
  return true;
}

// The stamps only (for messages).
Trajectory StampsOnly(const EvalTrajectory& t) {
  Trajectory out(t.size());
  for (size_t i = 0; i < t.size(); ++i) out[i].stamp = t.stamps[i];
  return out;
}

}  // namespace

bool AssociateByIndex(const Trajectory& ref, const Trajectory& est,
                      Association* association, std::string* error) {
  return AssociateBySize(ref.size(), est.size(), association, error);
}

namespace {

double MedianInterval(const Trajectory& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> d;
  d.reserve(t.size() - 1);
  for (size_t i = 1; i < t.size(); ++i) {
    d.push_back(NsToSeconds(t[i].stamp - t[i - 1].stamp));
  }
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

}  // namespace

std::string ExplainNoTimestampMatches(const Trajectory& ref,
                                      const Trajectory& est,
                                      const AssociationOptions& options) {
  if (ref.empty() || est.empty()) {
    return ref.empty() ? "the reference has no poses"
                       : "the estimate has no poses";
  }
  const double offset =
      std::isfinite(options.t_offset) ? options.t_offset : 0.0;
  const double r0 = NsToSeconds(ref.front().stamp);
  const double r1 = NsToSeconds(ref.back().stamp);
  const double e0 = NsToSeconds(est.front().stamp) + offset;
  const double e1 = NsToSeconds(est.back().stamp) + offset;
  std::string msg = "reference stamps span [" + Seconds(ref.front().stamp) +
                    ", " + Seconds(ref.back().stamp) +
                    "] s, estimate stamps (offset applied) span [" +
                    Format("%.6f", e0) + ", " + Format("%.6f", e1) + "] s";
  // Unit mismatch: magnitudes differing by about 1e3, 1e6 or 1e9.
  const double mr = std::max(std::fabs(r0), std::fabs(r1));
  const double me = std::max(std::fabs(e0), std::fabs(e1));
  if (mr > 0.0 && me > 0.0) {
    const double ratio = std::log10(std::max(mr, me) / std::min(mr, me));
    for (const auto& unit : {std::make_pair(3.0, "milliseconds"),
                             std::make_pair(6.0, "microseconds"),
                             std::make_pair(9.0, "nanoseconds")}) {
      if (std::fabs(ratio - unit.first) < 0.5) {
        msg += std::string("; the ") + (me > mr ? "estimate" : "reference") +
               "'s stamps are about 1e" + Format("%.0f", unit.first) +
               " times larger: one file seems to hold " + unit.second +
               " where seconds are expected (TUM stamps are seconds, EuRoC "
               "stamps nanoseconds: check --format)";
        return msg;
      }
    }
  }
  if (e1 < r0 || e0 > r1) {
    msg +=
        "; the time ranges do not overlap: if both start together, try "
        "--t_offset " +
        Format("%.6f", r0 - NsToSeconds(est.front().stamp));
    return msg;
  }
  // Overlapping but nothing close enough: report the closest difference.
  double closest = std::numeric_limits<double>::infinity();
  for (const auto& p : est) {
    const double t = NsToSeconds(p.stamp) + offset;
    auto it = std::lower_bound(ref.begin(), ref.end(), t,
                               [](const StampedPose& a, double b) {
                                 return NsToSeconds(a.stamp) < b;
                               });
    if (it != ref.end()) {
      closest = std::min(closest, std::fabs(NsToSeconds(it->stamp) - t));
    }
    if (it != ref.begin()) {
      closest =
          std::min(closest, std::fabs(NsToSeconds(std::prev(it)->stamp) - t));
    }
  }
  msg += "; the closest pair of stamps is " + Format("%.6f", closest) +
         " s apart (> t_max_diff " + Format("%g", options.t_max_diff) +
         " s; median sampling intervals: reference " +
         Format("%.6f", MedianInterval(ref)) + " s, estimate " +
         Format("%.6f", MedianInterval(est)) +
         " s): raise --t_max_diff or set --t_offset";
  return msg;
}

// ----------------------------------------------------------------- alignment

const char* AlignmentMethodName(AlignmentMethod method) {
  switch (method) {
    case AlignmentMethod::kNone:
      return "none";
    case AlignmentMethod::kSE3:
      return "se3";
    case AlignmentMethod::kSim3:
      return "sim3";
    case AlignmentMethod::kScale:
      return "scale";
    case AlignmentMethod::kOrigin:
      return "origin";
  }
  return "?";
}

bool ParseAlignmentMethod(const std::string& name, AlignmentMethod* method) {
  for (AlignmentMethod m :
       {AlignmentMethod::kNone, AlignmentMethod::kSE3, AlignmentMethod::kSim3,
        AlignmentMethod::kScale, AlignmentMethod::kOrigin}) {
    if (name == AlignmentMethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

Pose3 Similarity3::Apply(const Pose3& pose) const {
  return Pose3(Apply(pose.t), Eigen::Quaterniond(rotation) * pose.q);
}

MatrixPose Similarity3::Apply(const MatrixPose& pose) const {
  return MatrixPose(rotation * pose.r,
                    rotation * (scale * pose.t) + translation);
}

bool UmeyamaAlignment(const std::vector<Eigen::Vector3d>& x,
                      const std::vector<Eigen::Vector3d>& y, bool with_scale,
                      Similarity3* result, std::string* error) {
  if (x.size() != y.size()) {
    *error = "alignment needs as many points in both sets";
    return false;
  }
  if (x.size() < 2) {
    *error = "alignment needs at least 2 matched positions (got " +
             std::to_string(x.size()) + ")";
    return false;
  }
  const double n = static_cast<double>(x.size());
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_y = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= n;
  mean_y /= n;
  double sigma_x = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    const Eigen::Vector3d dx = x[i] - mean_x;
    sigma_x += dx.squaredNorm();
    cov += (y[i] - mean_y) * dx.transpose();
  }
  sigma_x /= n;
  cov /= n;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] > std::numeric_limits<double>::epsilon()) ++rank;
  }
  if (rank < 2) {
    *error =
        "degenerate covariance rank (the matched positions are "
        "collinear or identical): Umeyama alignment is not possible";
    return false;
  }
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) {
    s(2, 2) = -1.0;  // Keep a proper rotation (det +1).
  }
  result->rotation = svd.matrixU() * s * svd.matrixV().transpose();
  result->scale = with_scale ? (d.asDiagonal() * s).trace() / sigma_x : 1.0;
  result->translation = mean_y - result->scale * (result->rotation * mean_x);
  return true;
}

bool ComputeAlignment(const std::vector<Pose3>& ref,
                      const std::vector<Pose3>& est, AlignmentMethod method,
                      int n_to_align, Similarity3* result, std::string* error) {
  return ComputeAlignment(ToMatrixPoses(ref), ToMatrixPoses(est), method,
                          n_to_align, result, error);
}

bool ComputeAlignment(const std::vector<MatrixPose>& ref,
                      const std::vector<MatrixPose>& est,
                      AlignmentMethod method, int n_to_align,
                      Similarity3* result, std::string* error) {
  *result = Similarity3();
  if (ref.size() != est.size()) {
    *error = "alignment needs matched trajectories of equal size";
    return false;
  }
  if (method == AlignmentMethod::kNone) return true;
  if (ref.empty()) {
    *error = "cannot align empty trajectories";
    return false;
  }
  if (method == AlignmentMethod::kOrigin) {
    // T = P_ref,0 * P_est,0^-1 (evo's se3_inverse), applied on the left.
    const MatrixPose t = ref[0] * est[0].TransposeInverse();
    result->rotation = t.r;
    result->translation = t.t;
    result->scale = 1.0;
    return true;
  }
  size_t n = est.size();
  if (n_to_align > 0) n = std::min(n, static_cast<size_t>(n_to_align));
  std::vector<Eigen::Vector3d> x(n);
  std::vector<Eigen::Vector3d> y(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = est[i].t;
    y[i] = ref[i].t;
  }
  Similarity3 umeyama;
  const bool with_scale = method != AlignmentMethod::kSE3;
  if (!UmeyamaAlignment(x, y, with_scale, &umeyama, error)) return false;
  if (method == AlignmentMethod::kScale) {
    result->scale = umeyama.scale;  // Scale only (evo -s without -a).
  } else {
    *result = umeyama;
  }
  return true;
}

std::vector<MatrixPose> ApplyAlignment(const Similarity3& transform,
                                       const std::vector<MatrixPose>& poses) {
  std::vector<MatrixPose> out;
  out.reserve(poses.size());
  for (const MatrixPose& p : poses) out.push_back(transform.Apply(p));
  return out;
}

std::vector<Pose3> ApplyAlignment(const Similarity3& transform,
                                  const std::vector<Pose3>& poses) {
  std::vector<Pose3> out;
  out.reserve(poses.size());
  for (const Pose3& p : poses) out.push_back(transform.Apply(p));
  return out;
}

// -------------------------------------------------------------------- metrics

double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::fabs(q.w()));
}

double RotationAngleOfMatrix(const Eigen::Matrix3d& m) {
  // scipy Rotation.from_matrix (Markley 2008): the branch of the largest of
  // the diagonal entries and the trace, then normalization.
  const double trace = m(0, 0) + m(1, 1) + m(2, 2);
  int choice = 3;
  double largest = trace;
  for (int i = 0; i < 3; ++i) {
    if (m(i, i) > largest) {
      largest = m(i, i);
      choice = i;
    }
  }
  double q[4];  // x, y, z, w.
  if (choice != 3) {
    const int i = choice, j = (i + 1) % 3, k = (j + 1) % 3;
    q[i] = 1.0 - trace + 2.0 * m(i, i);
    q[j] = m(j, i) + m(i, j);
    q[k] = m(k, i) + m(i, k);
    q[3] = m(k, j) - m(j, k);
  } else {
    q[0] = m(2, 1) - m(1, 2);
    q[1] = m(0, 2) - m(2, 0);
    q[2] = m(1, 0) - m(0, 1);
    q[3] = 1.0 + trace;
  }
  const double norm =
      std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& x : q) x /= norm;
  // as_rotvec: w >= 0, angle = 2 atan2(|v|, w), rotvec = angle / sin(angle
  // / 2) * v (a series near 0); the angle returned is |rotvec|.
  if (q[3] < 0.0) {
    for (double& x : q) x = -x;
  }
  const double v = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const double angle = 2.0 * std::atan2(v, q[3]);
  const double a2 = angle * angle;
  const double scale = angle <= 1e-3 ? 2.0 + a2 / 12.0 + 7.0 * a2 * a2 / 2880.0
                                     : angle / std::sin(angle / 2.0);
  const double x = scale * q[0], y = scale * q[1], z = scale * q[2];
  return std::sqrt(x * x + y * y + z * z);
}

std::vector<double> ApeTranslationErrors(const std::vector<MatrixPose>& ref,
                                         const std::vector<MatrixPose>& est) {
  std::vector<double> e(std::min(ref.size(), est.size()));
  for (size_t i = 0; i < e.size(); ++i) e[i] = (est[i].t - ref[i].t).norm();
  return e;
}

std::vector<double> ApeTranslationErrors(const std::vector<Pose3>& ref,
                                         const std::vector<Pose3>& est) {
  return ApeTranslationErrors(ToMatrixPoses(ref), ToMatrixPoses(est));
}

std::vector<double> ApeRotationErrorsDeg(const std::vector<MatrixPose>& ref,
                                         const std::vector<MatrixPose>& est) {
  std::vector<double> e(std::min(ref.size(), est.size()));
  for (size_t i = 0; i < e.size(); ++i) {
    // evo: so3_log_angle of (P_est^-1 P_ref)'s 3x3 block, in degrees.
    e[i] =
        RotationAngleOfMatrix(est[i].r.transpose() * ref[i].r) * 180.0 / M_PI;
  }
  return e;
}

std::vector<double> ApeRotationErrorsDeg(const std::vector<Pose3>& ref,
                                         const std::vector<Pose3>& est) {
  return ApeRotationErrorsDeg(ToMatrixPoses(ref), ToMatrixPoses(est));
}

const char* DeltaUnitName(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::kFrames:
      return "frames";
    case DeltaUnit::kMeters:
      return "m";
    case DeltaUnit::kSeconds:
      return "s";
  }
  return "?";
}

bool ParseDeltaUnit(const std::string& name, DeltaUnit* unit) {
  if (name == "frames" || name == "f" || name == "frame") {
    *unit = DeltaUnit::kFrames;
  } else if (name == "m" || name == "meters" || name == "metres") {
    *unit = DeltaUnit::kMeters;
  } else if (name == "s" || name == "seconds") {
    *unit = DeltaUnit::kSeconds;
  } else {
    return false;
  }
  return true;
}

namespace {

// First index j in [lo, hi) with !(key(j) < value), key non-decreasing.
template <typename Key>
size_t LowerBoundIndex(size_t lo, size_t hi, double value, const Key& key) {
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (key(mid) < value) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// For each i: the j > i whose key(j) - key(i) is closest to delta (first on a
// tie, like numpy's argmin), kept within tol. `values` non-decreasing.
IndexPairs ClosestDeltaPairs(const std::vector<double>& values, double delta,
                             double tol) {
  IndexPairs pairs;
  const size_t n = values.size();
  for (size_t i = 0; i + 1 < n; ++i) {
    auto f = [&](size_t j) { return values[j] - values[i]; };
    const size_t k = LowerBoundIndex(i + 1, n, delta, f);
    size_t best = n;
    double best_res = std::numeric_limits<double>::infinity();
    if (k > i + 1) {
      // Below delta: the first index holding the same difference as k - 1.
      const double v = f(k - 1);
      const size_t first = LowerBoundIndex(i + 1, k, v, f);
      best = first;
      best_res = std::fabs(v - delta);
    }
    if (k < n && std::fabs(f(k) - delta) < best_res) {
      best = k;
      best_res = std::fabs(f(k) - delta);
    }
    if (best < n && !(best_res > tol)) pairs.emplace_back(i, best);
  }
  return pairs;
}

}  // namespace

bool SelectRpePairs(const std::vector<Pose3>& poses,
                    const std::vector<TimeNs>& stamps,
                    const RpeOptions& options, IndexPairs* pairs,
                    std::string* error) {
  return SelectRpePairs(ToMatrixPoses(poses), stamps, options, pairs, error);
}

bool SelectRpePairs(const std::vector<MatrixPose>& poses,
                    const std::vector<TimeNs>& stamps,
                    const RpeOptions& options, IndexPairs* pairs,
                    std::string* error) {
  pairs->clear();
  const size_t n = poses.size();
  if (!(options.delta > 0.0) || !std::isfinite(options.delta)) {
    *error = "the RPE delta must be a positive number";
    return false;
  }
  switch (options.unit) {
    case DeltaUnit::kFrames: {
      if (options.delta != std::floor(options.delta)) {
        *error = "the RPE delta must be an integer for the unit frames";
        return false;
      }
      // A delta of n frames or more gives no pair (and would not fit a
      // size_t from 2^64 on).
      if (options.delta >= static_cast<double>(n)) break;
      const size_t d = static_cast<size_t>(options.delta);
      if (options.all_pairs) {
        for (size_t i = 0; i + d < n; ++i) pairs->emplace_back(i, i + d);
      } else {
        for (size_t i = 0; i + d < n; i += d) pairs->emplace_back(i, i + d);
      }
      break;
    }
    case DeltaUnit::kMeters: {
      if (options.all_pairs) {
        std::vector<double> dist(n, 0.0);
        for (size_t i = 1; i < n; ++i) {
          dist[i] = dist[i - 1] + (poses[i].t - poses[i - 1].t).norm();
        }
        *pairs = ClosestDeltaPairs(dist, options.delta,
                                   options.delta * options.rel_delta_tol);
      } else {
        // evo's filter_pairs_by_path: the accumulator starts at pose 0 and
        // restarts at 0 at every recorded index.
        std::vector<size_t> ids;
        double current = 0.0;
        for (size_t i = 0; i < n; ++i) {
          if (i > 0) current += (poses[i].t - poses[i - 1].t).norm();
          if (current >= options.delta) {
            ids.push_back(i);
            current = 0.0;
          }
        }
        for (size_t k = 0; k + 1 < ids.size(); ++k) {
          pairs->emplace_back(ids[k], ids[k + 1]);
        }
      }
      break;
    }
    case DeltaUnit::kSeconds: {
      if (stamps.size() != n) {
        *error = "the RPE unit seconds needs stamps for every pose";
        return false;
      }
      if (options.all_pairs) {
        std::vector<double> t(n);
        for (size_t i = 0; i < n; ++i) {
          t[i] = SecondsBetween(stamps[0], stamps[i]);
        }
        *pairs = ClosestDeltaPairs(t, options.delta,
                                   options.delta * options.rel_delta_tol);
      } else {
        // A delta longer than the whole trajectory gives no pair (and would
        // overflow int64 nanoseconds from about 9.2e9 s on).
        if (n == 0 ||
            options.delta > SecondsBetween(stamps[0], stamps.back())) {
          break;
        }
        // In 128 bits: the span of int64 stamps exceeds int64.
        const __int128 d =
            static_cast<__int128>(std::round(options.delta * 1e9));
        size_t start = 0;
        for (size_t j = 1; j < n; ++j) {
          if (static_cast<__int128>(stamps[j]) - stamps[start] >= d) {
            pairs->emplace_back(start, j);
            start = j;
          }
        }
      }
      break;
    }
  }
  if (pairs->empty()) {
    *error = "RPE delta = " + Format("%g", options.delta) + " (" +
             DeltaUnitName(options.unit) + ") produced no pose pair among " +
             std::to_string(n) +
             " poses: try a lower delta or a less strict tolerance";
    return false;
  }
  return true;
}

bool ComputeRpe(const std::vector<Pose3>& ref, const std::vector<Pose3>& est,
                const std::vector<TimeNs>& ref_stamps,
                const std::vector<TimeNs>& est_stamps,
                const RpeOptions& options, RpeErrors* errors,
                std::string* error) {
  return ComputeRpe(ToMatrixPoses(ref), ToMatrixPoses(est), ref_stamps,
                    est_stamps, options, errors, error);
}

bool ComputeRpe(const std::vector<MatrixPose>& ref,
                const std::vector<MatrixPose>& est,
                const std::vector<TimeNs>& ref_stamps,
                const std::vector<TimeNs>& est_stamps,
                const RpeOptions& options, RpeErrors* errors,
                std::string* error) {
  *errors = RpeErrors();
  if (ref.size() != est.size()) {
    *error = "RPE needs matched trajectories of equal size";
    return false;
  }
  const bool from_ref = options.pairs_from_reference;
  if (!SelectRpePairs(from_ref ? ref : est, from_ref ? ref_stamps : est_stamps,
                      options, &errors->pairs, error)) {
    return false;
  }
  errors->translation.reserve(errors->pairs.size());
  errors->rotation_deg.reserve(errors->pairs.size());
  for (const auto& [i, j] : errors->pairs) {
    const MatrixPose q_rel = Between(ref[i], ref[j]);
    const MatrixPose p_rel = Between(est[i], est[j]);
    const MatrixPose e = Between(q_rel, p_rel);
    errors->translation.push_back(e.t.norm());
    errors->rotation_deg.push_back(RotationAngleOfMatrix(e.r) * 180.0 / M_PI);
  }
  return true;
}

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

double PathLength(const std::vector<MatrixPose>& poses) {
  double length = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    length += (poses[i].t - poses[i - 1].t).norm();
  }
  return length;
}

double PathLength(const std::vector<Pose3>& poses) {
  return PathLength(ToMatrixPoses(poses));
}

// ------------------------------------------------------------- whole pipeline

bool EvaluateTrajectories(const Trajectory& ref, const Trajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error) {
  return EvaluateTrajectories(ToEvalTrajectory(ref), ToEvalTrajectory(est),
                              settings, result, error);
}

bool EvaluateTrajectories(const EvalTrajectory& ref, const EvalTrajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error) {
  *result = EvalResult();
  if (ref.empty()) {
    *error = "the reference trajectory has no poses";
    return false;
  }
  if (est.empty()) {
    *error = "the estimated trajectory has no poses";
    return false;
  }
  if (settings.association == AssociationMethod::kIndex) {
    if (!AssociateBySize(ref.size(), est.size(), &result->association, error)) {
      return false;
    }
  } else {
    if (!CheckAssociationOptions(settings.sync, error)) return false;
    result->association = AssociateByTimestamp(ref, est, settings.sync);
    if (result->association.size() == 0) {
      *error =
          "found no matching timestamps between the reference and the "
          "estimate with max. time diff " +
          Format("%g", settings.sync.t_max_diff) + " s and time offset " +
          Format("%g", settings.sync.t_offset) + " s: " +
          ExplainNoTimestampMatches(StampsOnly(ref), StampsOnly(est),
                                    settings.sync);
      return false;
    }
  }
  const Association& a = result->association;
  result->ref.reserve(a.size());
  result->ref_stamps.reserve(a.size());
  result->est.reserve(a.size());
  result->est_stamps.reserve(a.size());
  for (size_t k = 0; k < a.size(); ++k) {
    result->ref.push_back(ref.poses[a.ref_indices[k]]);
    result->ref_stamps.push_back(ref.stamps[a.ref_indices[k]]);
    result->est.push_back(est.poses[a.est_indices[k]]);
    result->est_stamps.push_back(est.stamps[a.est_indices[k]]);
  }
  if (!ComputeAlignment(result->ref, result->est, settings.align,
                        settings.n_to_align, &result->alignment, error)) {
    *error = "alignment (" + std::string(AlignmentMethodName(settings.align)) +
             ") of " + std::to_string(a.size()) + " matched poses: " + *error;
    return false;
  }
  result->est_aligned = ApplyAlignment(result->alignment, result->est);
  result->ref_path_length = PathLength(result->ref);
  result->est_path_length = PathLength(result->est_aligned);

  result->ape_translation =
      ApeTranslationErrors(result->ref, result->est_aligned);
  result->ape_rotation_deg =
      ApeRotationErrorsDeg(result->ref, result->est_aligned);
  result->ape_translation_stats =
      ComputeErrorStatistics(result->ape_translation);
  result->ape_rotation_stats = ComputeErrorStatistics(result->ape_rotation_deg);

  if (!ComputeRpe(result->ref, result->est_aligned, result->ref_stamps,
                  result->est_stamps, settings.rpe, &result->rpe, error)) {
    return false;
  }
  result->rpe_translation_stats =
      ComputeErrorStatistics(result->rpe.translation);
  result->rpe_rotation_stats = ComputeErrorStatistics(result->rpe.rotation_deg);

  if (settings.kitti) {
    result->has_kitti = true;
    // The devkit does not align; a rigid alignment leaves relative poses
    // unchanged, so only a scale correction is applied (see the header).
    const bool scaled = settings.align == AlignmentMethod::kSim3 ||
                        settings.align == AlignmentMethod::kScale;
    if (!ComputeKittiMetric(result->ref,
                            scaled ? result->est_aligned : result->est,
                            &result->kitti, error)) {
      return false;
    }
  }
  return true;
}

namespace {
std::string FormatG(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}
}  // namespace

std::string DescribeRpeOptions(const RpeOptions& r) {
  std::string s =
      "delta " + FormatG(r.delta) + " " + DeltaUnitName(r.unit) + ", " +
      (r.all_pairs ? "all pairs" : "consecutive pairs") +
      ", pairs chosen on the " +
      (r.pairs_from_reference ? "reference" : "estimate (evo's default)");
  if (r.all_pairs && r.unit != DeltaUnit::kFrames) {
    s += ", tolerance " + FormatG(r.rel_delta_tol * 100.0) + " %";
  }
  return s;
}

// ------------------------------------------------------ relation-based error

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

namespace {

// The pose of `est` at `stamp` (see ComputeRelationError); false when there
// is none. *interpolated tells which way it was found.
bool PoseAt(const Trajectory& est, TimeNs stamp,
            const RelationErrorOptions& options, Pose3* pose,
            bool* interpolated) {
  const auto later = std::lower_bound(
      est.begin(), est.end(), stamp,
      [](const StampedPose& p, TimeNs t) { return p.stamp < t; });
  // Nearest stamp: the first at or after `stamp`, or the one before.
  auto nearest = later;
  if (later == est.end() ||
      (later != est.begin() &&
       stamp - std::prev(later)->stamp <= later->stamp - stamp)) {
    nearest = std::prev(later);
  }
  const double dt = std::fabs(NsToSeconds(nearest->stamp - stamp));
  if (dt <= options.t_max_diff) {
    *pose = nearest->pose;
    *interpolated = false;
    return true;
  }
  if (!options.interpolate || later == est.end() || later == est.begin()) {
    return false;
  }
  const StampedPose& a = *std::prev(later);
  const StampedPose& b = *later;
  const double f = static_cast<double>(stamp - a.stamp) /
                   static_cast<double>(b.stamp - a.stamp);
  *pose =
      Pose3(a.pose.t + f * (b.pose.t - a.pose.t), a.pose.q.slerp(f, b.pose.q));
  *interpolated = true;
  return true;
}

std::string SecondsText(TimeNs t) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6f", NsToSeconds(t));
  return buf;
}

}  // namespace

bool ComputeRelationError(const Trajectory& est,
                          const std::vector<PoseRelation>& relations,
                          const RelationErrorOptions& options,
                          RelationErrorResult* result, std::string* error) {
  *result = RelationErrorResult();
  result->relations = relations.size();
  if (!(options.t_max_diff >= 0.0)) {
    *error = "relations: t_max_diff must be >= 0";
    return false;
  }
  if (est.empty()) {
    *error = "relations: the estimate has no poses";
    return false;
  }
  for (size_t i = 1; i < est.size(); ++i) {
    if (est[i].stamp <= est[i - 1].stamp) {
      *error =
          "relations: the estimate's stamps must increase strictly (pose " +
          std::to_string(i) + " at " + SecondsText(est[i].stamp) + " s after " +
          SecondsText(est[i - 1].stamp) + " s)";
      return false;
    }
  }
  std::vector<double> translation_sq, rotation_sq;
  for (size_t k = 0; k < relations.size(); ++k) {
    const PoseRelation& r = relations[k];
    Pose3 x1, x2;
    bool i1 = false, i2 = false;
    if (!PoseAt(est, r.t1, options, &x1, &i1) ||
        !PoseAt(est, r.t2, options, &x2, &i2)) {
      ++result->unmatched;
      continue;
    }
    const Pose3 e = r.delta.Inverse() * (x1.Inverse() * x2);
    const double t = e.t.norm();
    const double rot = RotationAngle(e.q) * 180.0 / M_PI;
    result->used.push_back(k);
    result->interpolated += (i1 || i2) ? 1 : 0;
    result->translation.push_back(t);
    result->rotation_deg.push_back(rot);
    translation_sq.push_back(t * t);
    rotation_sq.push_back(rot * rot);
  }
  if (result->used.empty()) {
    *error = "relations: none of the " + std::to_string(relations.size()) +
             " relations has poses in the estimate (estimate stamps " +
             SecondsText(est.front().stamp) + " .. " +
             SecondsText(est.back().stamp) + " s";
    if (!relations.empty()) {
      *error += ", first relation " + SecondsText(relations.front().t1) +
                " -> " + SecondsText(relations.front().t2) + " s";
    }
    *error += options.interpolate
                  ? ")"
                  : "; stamps must match within " +
                        SecondsText(SecondsToNs(options.t_max_diff)) +
                        " s, or interpolate)";
    return false;
  }
  result->translation_abs = ComputeMeanStd(result->translation);
  result->translation_sq = ComputeMeanStd(translation_sq);
  result->rotation_abs = ComputeMeanStd(result->rotation_deg);
  result->rotation_sq = ComputeMeanStd(rotation_sq);
  return true;
}

}  // namespace slam
