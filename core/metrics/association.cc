#include "core/metrics/association.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>

#include "core/metrics/format.h"

namespace slam {

namespace {

using metrics_internal::Format;

std::string Seconds(TimeNs ns) { return Format("%.6f", NsToSeconds(ns)); }

}  // namespace

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

}  // namespace slam
