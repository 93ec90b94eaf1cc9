#include "core/metrics/ape_rpe.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "core/metrics/format.h"

namespace slam {

namespace {

using metrics_internal::Format;

// b - a in seconds, without int64 overflow for stamps of opposite signs.
double SecondsBetween(TimeNs a, TimeNs b) {
  return static_cast<double>(static_cast<__int128>(b) - a) * 1e-9;
}

// Relative pose a^-1 b (evo's relative_se3: the transpose as inverse).
MatrixPose Between(const MatrixPose& a, const MatrixPose& b) {
  return a.TransposeInverse() * b;
}

}  // namespace

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

}  // namespace slam
