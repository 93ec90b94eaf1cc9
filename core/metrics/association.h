// Association of two trajectories by timestamp or by index.
//
// Association by timestamp (evo core/sync.py, associate_trajectories /
//   matching_time_indices): start from the trajectory with FEWER poses (the
//   estimate when both have as many); for each of its stamps take the stamp
//   of the other trajectory, shifted by the offset (the offset is added to
//   the ESTIMATE's stamps: evo adds it to the longer trajectory's stamps, or
//   subtracts it from the reference's when the estimate is the shorter one),
//   with the smallest |difference| (the first one on a tie, as numpy's
//   argmin, i.e. the first in file order) and keep the pair when that
//   difference is <= t_max_diff (default 0.01 s); stamps need not be sorted. As
//   evo, the stamps are compared as float64 seconds (EvalTrajectory::seconds,
//   the values evo parses from the file), so a stamp exactly halfway between
//   two others goes where evo's rounding puts it, and duplicate stamps are
//   allowed (the first of equal stamps wins). As evo, a pose of the longer
//   trajectory may be paired twice when t_max_diff is at least half its
//   sampling interval (Association::reused_poses counts such pairs).
//   unique_pairs (slam eval
//   --unique_pairs; a deviation from evo) keeps pairs one-to-one instead: of
//   pairs that share a pose, the one with the smallest |difference| stays
//   (the earliest on a tie); the others are counted in dropped_duplicates.
// Association by index: pose i with pose i; both must have as many poses
//   (evo raises "trajectories must have same number of poses").
#ifndef SLAM_CORE_METRICS_ASSOCIATION_H_
#define SLAM_CORE_METRICS_ASSOCIATION_H_

#include <cstddef>
#include <string>
#include <vector>

#include "core/conventions.h"
#include "core/metrics/matrix_pose.h"
#include "core/trajectory.h"

namespace slam {

struct AssociationOptions {
  double t_max_diff = 0.01;   // Seconds.
  double t_offset = 0.0;      // Seconds, added to the estimate's stamps.
  bool unique_pairs = false;  // One-to-one pairs (not evo's behaviour).
};
// False with a message for a negative or NaN t_max_diff or a non-finite
// t_offset.
bool CheckAssociationOptions(const AssociationOptions& options,
                             std::string* error);

struct Association {
  bool by_index = false;
  // Matched pairs in time order: ref[ref_indices[k]] <-> est[est_indices[k]].
  std::vector<size_t> ref_indices;
  std::vector<size_t> est_indices;
  size_t max_pairs = 0;           // Poses of the shorter trajectory.
  size_t reused_poses = 0;        // Pairs whose pose of the longer
                                  // trajectory is also in an earlier pair.
  size_t dropped_duplicates = 0;  // unique_pairs: pairs removed.
  double max_abs_dt = 0.0;        // Largest |t_est + offset - t_ref| (s).
  size_t size() const { return ref_indices.size(); }
};

// Stamps in any order (as evo); options must pass CheckAssociationOptions.
Association AssociateByTimestamp(const EvalTrajectory& ref,
                                 const EvalTrajectory& est,
                                 const AssociationOptions& options);
Association AssociateByTimestamp(const Trajectory& ref, const Trajectory& est,
                                 const AssociationOptions& options);
// False with a message when the pose counts differ.
bool AssociateBySize(size_t ref_size, size_t est_size, Association* association,
                     std::string* error);
bool AssociateByIndex(const Trajectory& ref, const Trajectory& est,
                      Association* association, std::string* error);
// Why no stamp matched: time ranges, overlap, a unit mismatch (seconds vs
// nanoseconds or microseconds) or an offset that would make them overlap.
std::string ExplainNoTimestampMatches(const Trajectory& ref,
                                      const Trajectory& est,
                                      const AssociationOptions& options);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_ASSOCIATION_H_
