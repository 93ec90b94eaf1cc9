// Trajectory evaluation: association, alignment and error metrics, defined as
// evo (github.com/MichaelGrupp/evo) and the KITTI odometry devkit define them.
// Pure math: no file format, no command line (datasets/trajectory_io.h reads
// the files, apps/eval_report.h prints and plots).
//
// Definitions (with the evo source each one follows):
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
//
// Alignment of the estimate onto the reference (evo core/geometry.py
//   umeyama_alignment and core/trajectory.py PosePath3D.align/align_origin):
//   Umeyama (PAMI 1991) on the positions, x = estimate, y = reference:
//   means, sigma_x = 1/n sum |x_i - mean_x|^2, Sigma = 1/n sum (y_i -
//   mean_y)(x_i - mean_x)^T = U D V^T, S = diag(1, 1, det(U) det(V) < 0 ? -1
//   : 1), R = U S V^T, c = trace(D S) / sigma_x (Sim(3); 1 for SE(3)),
//   t = mean_y - c R mean_x. Fails when fewer than 2 singular values exceed
//   machine epsilon (evo: "Degenerate covariance rank"). The aligned estimate
//   is p' = c R p + t, R' = R R_p. n_to_align > 0 uses only the first n
//   matched pairs (evo --n_to_align). kScale applies only c (evo -s without
//   -a). kOrigin: T = P_ref,0 P_est,0^-1 applied on the left (evo
//   --align_origin).
//
// Poses are used as read (MatrixPose): a KITTI file's 3x3 blocks are not
//   exactly rotations (7 significant digits), and evo and the devkit use them
//   as they are; inverses are evo's se3_inverse [R^T | -R^T t] (the devkit's
//   KITTI metric: the true matrix inverse). A rotation is extracted only
//   where an angle is needed, as evo does (scipy Rotation.from_matrix: the
//   quaternion of Markley's four-branch method, normalized; RotationAngleDeg).
//   TUM/EuRoC quaternions are normalized and turned into matrices as evo
//   (transformations.quaternion_matrix).
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
//
// Statistics (evo PE.get_statistic): rmse = sqrt(mean(e^2)), mean, median
//   (numpy: mean of the two middle values for an even count), std
//   (population, ddof 0), min, max, sse = sum(e^2).
//
// KITTI odometry metric (devkit_odometry evaluate_odometry.cpp,
//   calcSequenceErrors + saveStats): reference path distances; for every
//   first frame 0, 10, 20, ... (step_size 10 frames) and every length L in
//   {100, ..., 800} m the last frame is the first whose distance exceeds
//   dist[first] + L (the segment is skipped when there is none); error pose
//   E = (P_f^-1 P_l)^-1 (Q_f^-1 Q_l); t_err = |t(E)| / L, r_err = acos(
//   clamp(0.5 (trace(R(E)) - 1))) / L. The result is the mean over all
//   segments (all lengths together, not a mean of per-length means):
//   t_rel_percent = 100 mean(t_err), r_rel_deg_per_100m = mean(r_err) * 180
//   / pi * 100. The devkit computes distances, the per-segment errors and
//   their sums in single precision (float); we do the same, so that segment
//   choice and rounding follow the devkit's. The devkit never aligns: the
//   metric uses the estimate as read, except with a scale alignment (sim3,
//   scale), where it uses the scaled estimate (rigid alignments do not change
//   relative poses).
#ifndef SLAM_CORE_METRICS_EVALUATION_H_
#define SLAM_CORE_METRICS_EVALUATION_H_

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/trajectory.h"

namespace slam {

// ------------------------------------------------------------------- poses
// A pose as evo holds it (a 4x4 matrix): the 3x3 block as given, not
// re-orthonormalized, and the translation.
struct MatrixPose {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  MatrixPose() = default;
  MatrixPose(const Eigen::Matrix3d& rr, const Eigen::Vector3d& tt)
      : r(rr), t(tt) {}
  // The unit quaternion's matrix as evo's transformations.quaternion_matrix.
  explicit MatrixPose(const Pose3& pose);

  MatrixPose operator*(const MatrixPose& o) const {
    return MatrixPose(r * o.r, r * o.t + t);
  }
  // evo's se3_inverse: [R^T | -R^T t] (the transpose, not the inverse).
  MatrixPose TransposeInverse() const {
    const Eigen::Matrix3d rt = r.transpose();
    return MatrixPose(rt, -(rt * t));
  }
  // The true inverse of the 4x4 matrix (the KITTI devkit's Matrix::inv).
  MatrixPose Inverse() const {
    const Eigen::Matrix3d ri = r.inverse();
    return MatrixPose(ri, -(ri * t));
  }
};
std::vector<MatrixPose> ToMatrixPoses(const std::vector<Pose3>& poses);

// A trajectory as the evaluation reads it: stamps in nanoseconds, the same
// stamps as evo's float64 seconds, and the poses as read.
struct EvalTrajectory {
  std::vector<TimeNs> stamps;
  std::vector<double> seconds;
  std::vector<MatrixPose> poses;
  size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
};
// The double nearest to ns * 1e-9 (what Python's float() gives for a stamp
// written with up to nine decimals).
double NearestSeconds(TimeNs ns);
// Seconds by NearestSeconds, quaternions as MatrixPose(Pose3).
EvalTrajectory ToEvalTrajectory(const Trajectory& trajectory);

// ---------------------------------------------------------------- statistics
struct ErrorStatistics {
  size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;
};
// All zero for an empty vector.
ErrorStatistics ComputeErrorStatistics(const std::vector<double>& errors);

// --------------------------------------------------------------- association
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
bool AssociateByIndex(const Trajectory& ref, const Trajectory& est,
                      Association* association, std::string* error);
// Why no stamp matched: time ranges, overlap, a unit mismatch (seconds vs
// nanoseconds or microseconds) or an offset that would make them overlap.
std::string ExplainNoTimestampMatches(const Trajectory& ref,
                                      const Trajectory& est,
                                      const AssociationOptions& options);

// ----------------------------------------------------------------- alignment
enum class AlignmentMethod { kNone, kSE3, kSim3, kScale, kOrigin };
const char* AlignmentMethodName(AlignmentMethod method);  // "none", "se3", ...
bool ParseAlignmentMethod(const std::string& name, AlignmentMethod* method);

// x -> scale * rotation * x + translation.
struct Similarity3 {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const {
    return scale * (rotation * p) + translation;
  }
  // Position scaled, rotated and moved; orientation rotated.
  Pose3 Apply(const Pose3& pose) const;
  // As evo's scale() then transform(): R' = R_a R, t' = R_a (c t) + t_a.
  MatrixPose Apply(const MatrixPose& pose) const;
};

// Least-squares y_i ~ c R x_i + t (Umeyama 1991, as evo). with_scale false:
// c = 1. False with a message for mismatched sizes, fewer than 2 points or a
// degenerate (collinear) configuration.
bool UmeyamaAlignment(const std::vector<Eigen::Vector3d>& x,
                      const std::vector<Eigen::Vector3d>& y, bool with_scale,
                      Similarity3* result, std::string* error);

// The transform that aligns `est` onto `ref` (matched, same size) with
// `method`; n_to_align > 0 restricts Umeyama to the first n pairs (<= 0: all).
bool ComputeAlignment(const std::vector<MatrixPose>& ref,
                      const std::vector<MatrixPose>& est,
                      AlignmentMethod method, int n_to_align,
                      Similarity3* result, std::string* error);
bool ComputeAlignment(const std::vector<Pose3>& ref,
                      const std::vector<Pose3>& est, AlignmentMethod method,
                      int n_to_align, Similarity3* result, std::string* error);
std::vector<MatrixPose> ApplyAlignment(const Similarity3& transform,
                                       const std::vector<MatrixPose>& poses);
std::vector<Pose3> ApplyAlignment(const Similarity3& transform,
                                  const std::vector<Pose3>& poses);

// -------------------------------------------------------------------- metrics
// Rotation angle of a unit quaternion, radians in [0, pi].
double RotationAngle(const Eigen::Quaterniond& q);
// Rotation angle of a 3x3 matrix that is a rotation up to rounding, as evo's
// so3_log_angle (scipy: Markley's quaternion, normalized, then |rotvec|).
double RotationAngleOfMatrix(const Eigen::Matrix3d& m);

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

// Devkit segment and summary; t_err in m/m, r_err in rad/m (as the devkit).
struct KittiSegmentError {
  size_t first_frame = 0;
  size_t last_frame = 0;
  double length = 0.0;
  double t_err = 0.0;
  double r_err = 0.0;
};
struct KittiLengthSummary {
  double length = 0.0;
  size_t count = 0;
  double t_rel_percent = 0.0;
  double r_rel_deg_per_100m = 0.0;
};
struct KittiMetric {
  size_t num_segments = 0;  // 0: trajectory shorter than 100 m (values NaN).
  double t_rel_percent = 0.0;
  double r_rel_deg_per_100m = 0.0;
  std::vector<KittiLengthSummary> by_length;  // Lengths with segments.
  std::vector<KittiSegmentError> segments;
};
// ref/est matched (same size), frame k of both at index k.
bool ComputeKittiMetric(const std::vector<MatrixPose>& ref,
                        const std::vector<MatrixPose>& est, KittiMetric* metric,
                        std::string* error);
bool ComputeKittiMetric(const std::vector<Pose3>& ref,
                        const std::vector<Pose3>& est, KittiMetric* metric,
                        std::string* error);

// Sum of distances between consecutive positions.
double PathLength(const std::vector<MatrixPose>& poses);
double PathLength(const std::vector<Pose3>& poses);

// ------------------------------------------------------ relation-based error
// The metric of Kuemmerle et al. 2009, "On measuring the accuracy of SLAM
// algorithms" (Autonomous Robots 27(4)): ground truth is a set of relations
// delta*_ij, the displacement of the pose at t2 in the frame of the pose at
// t1; the error of one relation is
//   e_ij = delta_ij (-) delta*_ij = delta*_ij^-1 delta_ij,
//   delta_ij = x(t1)^-1 x(t2),
// with translational part trans(e_ij) = |t(e_ij)| (metres; equal to
// |t(delta_ij) - t(delta*_ij)|) and rotational part rot(e_ij), the rotation
// angle of e_ij (degrees; |wrap(theta - theta*)| for planar poses). The paper
// defines eps(delta) = 1/N sum trans(e)^2 + rot(e)^2 and its tables (like
// Hess et al. 2016, Table II, computed with Cartographer's
// compute_relations_metrics) give mean +- standard deviation of the absolute
// values |trans|, |rot| and of the squares trans^2, rot^2 over the
// relations, separately. The standard deviation is the sample one (divisor
// N - 1, as compute_relations_metrics; 0 for a single relation).
// Cartographer's tool takes e = delta delta*^-1 instead, whose translation
// norm |t - R R*^T t*| differs from ours by the rotation error times |t*|.
//
// Poses at t1 and t2: the estimate's pose with the nearest stamp when within
// t_max_diff (default 1 ms). Otherwise, with interpolate, the pose
// interpolated between the two neighbouring poses (linear in position, slerp
// in rotation; only inside the trajectory's time range); else the relation
// is counted as unmatched and left out. 2D trajectories are lifted (z = 0,
// rotation about z), so the same code serves SE(2) and SE(3).
struct PoseRelation {
  TimeNs t1 = 0;
  TimeNs t2 = 0;
  Pose3 delta;  // Pose at t2 in the frame of the pose at t1.
};

struct RelationErrorOptions {
  double t_max_diff = 0.001;  // Seconds.
  bool interpolate = false;
};

struct MeanStd {
  double mean = 0.0;
  double std = 0.0;  // Sample standard deviation (N - 1).
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

struct RelationErrorResult {
  size_t relations = 0;             // Given.
  size_t unmatched = 0;             // Left out: a stamp without pose.
  size_t interpolated = 0;          // Used with at least one interpolated pose.
  std::vector<size_t> used;         // Indices of the relations used.
  std::vector<double> translation;  // |trans(e)| per used relation, m.
  std::vector<double> rotation_deg;  // |rot(e)| per used relation, deg.
  MeanStd translation_abs;           // m
  MeanStd translation_sq;            // m^2
  MeanStd rotation_abs;              // deg
  MeanStd rotation_sq;               // deg^2
};

// `est` must have strictly increasing stamps. False with a message when it
// does not, or when no relation could be used (with the time ranges).
bool ComputeRelationError(const Trajectory& est,
                          const std::vector<PoseRelation>& relations,
                          const RelationErrorOptions& options,
                          RelationErrorResult* result, std::string* error);

// ------------------------------------------------------------- whole pipeline
enum class AssociationMethod { kTimestamp, kIndex };

struct EvalSettings {
  AssociationMethod association = AssociationMethod::kTimestamp;
  AssociationOptions sync;
  AlignmentMethod align = AlignmentMethod::kSE3;
  int n_to_align = -1;  // <= 0: all pairs.
  RpeOptions rpe;
  bool kitti = false;              // Also the KITTI devkit metric.
  RelationErrorOptions relations;  // slam eval --relations.
};

// "delta 1 frames, consecutive pairs, pairs chosen on the estimate ...".
std::string DescribeRpeOptions(const RpeOptions& r);

struct EvalResult {
  Association association;
  // The matched poses, pair k in each; stamps of both (est stamps as read,
  // without the offset).
  std::vector<TimeNs> ref_stamps;
  std::vector<TimeNs> est_stamps;
  std::vector<MatrixPose> ref;
  std::vector<MatrixPose> est;          // As read.
  std::vector<MatrixPose> est_aligned;  // After the alignment.
  Similarity3 alignment;
  double ref_path_length = 0.0;  // Of the matched poses.
  double est_path_length = 0.0;  // Of the matched, aligned poses.

  std::vector<double> ape_translation;   // Per pair, metres.
  std::vector<double> ape_rotation_deg;  // Per pair, degrees.
  ErrorStatistics ape_translation_stats;
  ErrorStatistics ape_rotation_stats;

  RpeErrors rpe;
  ErrorStatistics rpe_translation_stats;
  ErrorStatistics rpe_rotation_stats;

  bool has_kitti = false;
  KittiMetric kitti;
};

// Associates, aligns and computes APE, RPE (and the KITTI metric when asked).
// False with a message (no matching stamps and why, too few pairs, a
// degenerate alignment, no RPE pair for the delta).
bool EvaluateTrajectories(const EvalTrajectory& ref, const EvalTrajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error);
bool EvaluateTrajectories(const Trajectory& ref, const Trajectory& est,
                          const EvalSettings& settings, EvalResult* result,
                          std::string* error);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_EVALUATION_H_
