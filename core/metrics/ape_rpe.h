// Absolute and relative pose errors (APE, RPE) of matched trajectories.
//
// APE (evo core/metrics.py, class APE), per matched pose i:
//   translation part: |t_est,i - t_ref,i| (metres);
//   rotation angle: angle of E_i = P_est,i^-1 P_ref,i in degrees.
// RPE (evo core/metrics.py, class RPE, after the TUM RGB-D benchmark), per
//   index pair (i, j): E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with Q the reference
//   and P the (aligned) estimate; translation part |t(E)|, rotation angle of
//   E in degrees.
//   Pairs (evo core/filters.py), chosen on the ESTIMATE by default (evo's
//   default; --pairs_from_reference in evo, pairs_from_reference here):
//   frames, consecutive: (0, d), (d, 2d), ...; all pairs: (i, i + d) for all
//     i with i + d < n.
//   metres (path length), consecutive: walk the poses accumulating the
//     distance between neighbours (starting at pose 0); each time the
//     accumulator reaches delta, record the index and reset the accumulator
//     to 0; pairs are consecutive recorded indices (so pose 0 is not a pair
//     start: evo's filter_pairs_by_path). All pairs: for each i < n - 1, the
//     j > i whose accumulated path from i is closest to delta (first on a
//     tie), kept when |path - delta| <= rel_delta_tol * delta.
//   seconds: NOT in evo (its delta units are f, m, d, r). Defined here the
//     same way as frames: consecutive pairs start at pose 0, the next pose
//     of a pair is the first whose stamp is >= the start's stamp + delta; all
//     pairs: for each i the j > i with stamp difference closest to delta
//     (first on a tie), kept when within rel_delta_tol * delta.
#ifndef SLAM_CORE_METRICS_APE_RPE_H_
#define SLAM_CORE_METRICS_APE_RPE_H_

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/metrics/matrix_pose.h"

namespace slam {

std::vector<double> ApeTranslationErrors(const std::vector<MatrixPose>& ref,
                                         const std::vector<MatrixPose>& est);
std::vector<double> ApeTranslationErrors(const std::vector<Pose3>& ref,
                                         const std::vector<Pose3>& est);
std::vector<double> ApeRotationErrorsDeg(const std::vector<MatrixPose>& ref,
                                         const std::vector<MatrixPose>& est);
std::vector<double> ApeRotationErrorsDeg(const std::vector<Pose3>& ref,
                                         const std::vector<Pose3>& est);

enum class DeltaUnit { kFrames, kMeters, kSeconds };
const char* DeltaUnitName(DeltaUnit unit);  // "frames", "m", "s"
// Accepts frames|f, m|meters, s|seconds.
bool ParseDeltaUnit(const std::string& name, DeltaUnit* unit);

struct RpeOptions {
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::kFrames;
  bool all_pairs = false;
  bool pairs_from_reference = false;  // evo's default: pairs from estimate.
  double rel_delta_tol = 0.1;         // all_pairs mode, metres and seconds.
};

using IndexPairs = std::vector<std::pair<size_t, size_t>>;

// Index pairs (i, j), i < j, for `options` on one trajectory (positions for
// metres, stamps for seconds; `stamps` may be empty otherwise). False with a
// message for a bad delta or when no pair results (also for a delta longer
// than the trajectory, however large).
bool SelectRpePairs(const std::vector<MatrixPose>& poses,
                    const std::vector<TimeNs>& stamps,
                    const RpeOptions& options, IndexPairs* pairs,
                    std::string* error);
bool SelectRpePairs(const std::vector<Pose3>& poses,
                    const std::vector<TimeNs>& stamps,
                    const RpeOptions& options, IndexPairs* pairs,
                    std::string* error);

struct RpeErrors {
  IndexPairs pairs;
  std::vector<double> translation;   // Metres.
  std::vector<double> rotation_deg;  // Degrees.
};
// ref/est matched (same size); ref_stamps/est_stamps are needed only for the
// seconds unit (pairs come from the stamps of the trajectory they are
// selected on).
bool ComputeRpe(const std::vector<MatrixPose>& ref,
                const std::vector<MatrixPose>& est,
                const std::vector<TimeNs>& ref_stamps,
                const std::vector<TimeNs>& est_stamps,
                const RpeOptions& options, RpeErrors* errors,
                std::string* error);
bool ComputeRpe(const std::vector<Pose3>& ref, const std::vector<Pose3>& est,
                const std::vector<TimeNs>& ref_stamps,
                const std::vector<TimeNs>& est_stamps,
                const RpeOptions& options, RpeErrors* errors,
                std::string* error);

// "delta 1 frames, consecutive pairs, pairs chosen on the estimate ...".
std::string DescribeRpeOptions(const RpeOptions& r);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_APE_RPE_H_
