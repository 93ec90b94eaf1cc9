// Reading and writing trajectory files: TUM, KITTI poses, EuRoC CSV and the
// pose nodes of a g2o file. Inside, stamps are int64 nanoseconds and poses
// follow core/conventions.h; conversions happen here.
//
// Formats:
//   tum    "t x y z qx qy qz qw" per line, t in seconds (read exactly to the
//          nanosecond from the decimal text). Stamps above 1e12 (nanoseconds
//          or microseconds written where seconds belong) are rejected with a
//          hint. Lines starting with '#' and blank lines are skipped.
//   kitti  12 numbers per line, the 3x4 row-major [R | t] of the pose; no
//          stamps. The 3x3 part must be a rotation to 1e-3. Pose3 holds the
//          nearest rotation (published files carry 7 significant digits);
//          TrajectoryData::matrices keeps the blocks as read, which the
//          evaluation uses (as evo and the devkit do). An optional times file
//          (one stamp in seconds per line, as KITTI's times.txt) gives the
//          stamps; without it the pose index serves as stamp (in seconds) and
//          has_stamps is false, so the evaluation associates by index.
//   euroc  CSV, "timestamp [ns], px, py, pz, qw, qx, qy, qz[, more columns]":
//          state_groundtruth_estimate0/data.csv (17 columns) and estimate CSVs
//          (8 columns). Stamps are integer nanoseconds; quaternions w first.
//          Header lines start with '#' (a first line of column names is also
//          skipped). A directory is accepted: DIR/state_groundtruth_estimate0/
//          data.csv or DIR/mav0/state_groundtruth_estimate0/data.csv.
//   g2o    The pose vertices of a pose-graph file, read with the project's
//          reader (datasets/g2o_io.h ReadPoseGraph: g2o, or TORO by content):
//          VERTEX_SE2 "id x y theta" (lifted to 3D: z 0, rotation about z),
//          VERTEX_SE3:QUAT "id x y z qx qy qz qw". The stamp is the id in
//          seconds (so ids associate one-to-one with the default
//          t_max_diff), poses sorted by id. A file without vertices is an
//          error (its poses would only be an initial guess from the edges).
// Detection (format auto) looks at the content: a g2o keyword (VERTEX_*,
// EDGE_*), commas (euroc), 12 fields (kitti) or 8 fields (tum); a .g2o or
// .csv extension decides when the content does not.
//
// Errors name the place: "PATH:LINE: problem". Stamps must increase strictly
// (a non-monotonic or duplicate stamp is an error naming both lines; nothing
// is sorted or dropped silently); g2o ids must be unique. With
// allow_duplicate_stamps / allow_unsorted_stamps (slam eval, as evo reads
// such files) equal / decreasing stamps are kept in file order and
// described in TrajectoryData::warning.
// Numbers are parsed with std::from_chars (datasets/text_util.h).
// Writers build the whole file in memory and replace the target atomically
// (temporary file + rename); TUM stamps are written exactly, with nine
// decimals, values with 17 significant digits (exact round trip).
#ifndef SLAM_DATASETS_TRAJECTORY_IO_H_
#define SLAM_DATASETS_TRAJECTORY_IO_H_

#include <string>

#include <vector>

#include <Eigen/Core>

#include "core/graph.h"
#include "core/metrics/matrix_pose.h"
#include "core/trajectory.h"

namespace slam {

enum class TrajectoryFormat { kAuto, kTum, kKitti, kEuroc, kG2o };
const char* TrajectoryFormatName(TrajectoryFormat format);  // "tum", ...
// "auto", "tum", "kitti", "euroc", "g2o".
bool ParseTrajectoryFormat(const std::string& name, TrajectoryFormat* format);

struct TrajectoryReadOptions {
  TrajectoryFormat format = TrajectoryFormat::kAuto;
  std::string kitti_times_path;         // KITTI only: one stamp (s) per pose.
  bool allow_duplicate_stamps = false;  // Non-decreasing stamps suffice.
  bool allow_unsorted_stamps = false;   // Decreasing ones too (file order).
};

struct TrajectoryData {
  Trajectory poses;
  TrajectoryFormat format = TrajectoryFormat::kAuto;  // As read.
  bool has_stamps = true;  // False: KITTI without times (stamp = index s).
  std::string path;        // The file read (EuRoC: data.csv in a folder).
  // The stamps as evo holds them, float64 seconds: TUM and KITTI times as
  // parsed from the text, EuRoC nanoseconds / 1e9, KITTI without times the
  // index. Empty for g2o (ToEvalTrajectory derives them).
  std::vector<double> seconds;
  // KITTI: the 3x3 blocks as read (poses hold the nearest rotations).
  std::vector<Eigen::Matrix3d> matrices;
  size_t duplicate_stamps = 0;  // With allow_duplicate_stamps.
  size_t unsorted_stamps = 0;   // With allow_unsorted_stamps.
  std::string warning;          // Non-empty: something to tell the user.
};

// The trajectory as the evaluation uses it: the seconds and matrices above
// where the file has them.
EvalTrajectory ToEvalTrajectory(const TrajectoryData& data);

// The format of a file from its content (and extension), or an error.
bool DetectTrajectoryFormat(const std::string& path, TrajectoryFormat* format,
                            std::string* error);

bool ReadTrajectory(const std::string& path,
                    const TrajectoryReadOptions& options, TrajectoryData* data,
                    std::string* error);

bool ReadTumTrajectory(const std::string& path, Trajectory* trajectory,
                       std::string* error);
// times_path empty: stamps are the pose index in seconds, *has_stamps false.
bool ReadKittiPoses(const std::string& path, const std::string& times_path,
                    Trajectory* trajectory, bool* has_stamps,
                    std::string* error);
bool ReadEurocTrajectory(const std::string& path, Trajectory* trajectory,
                         std::string* error);
bool ReadG2oPoses(const std::string& path, Trajectory* trajectory,
                  std::string* error);

// kTum, kKitti (poses only; see WriteKittiTimes), kEuroc, kG2o (VERTEX_SE3:QUAT
// with id = stamp in whole seconds, or the index when a stamp is not whole).
bool WriteTrajectory(const std::string& path, const Trajectory& trajectory,
                     TrajectoryFormat format, std::string* error);
// One stamp per line in seconds (KITTI times.txt).
bool WriteKittiTimes(const std::string& path, const Trajectory& trajectory,
                     std::string* error);

// The pose nodes (pose2 lifted, pose3) of a graph, sorted by stamp. Stamps:
// the node id in seconds (as ReadG2oPoses), or the node's own stamp when
// use_node_stamps and it has one. False when two nodes get the same stamp.
bool TrajectoryFromGraph(const Graph& graph, bool use_node_stamps,
                         Trajectory* trajectory, std::string* error);

// "12.345678901" (nine decimals, exact) for a stamp in nanoseconds.
std::string FormatStampSeconds(TimeNs stamp);
// Parses decimal seconds exactly to nanoseconds (rounding beyond the ninth
// decimal); exponents are accepted through double. False if not a number.
bool ParseStampSeconds(const std::string& text, TimeNs* stamp);

}  // namespace slam

#endif  // SLAM_DATASETS_TRAJECTORY_IO_H_
