// Reading and writing 2D graphs in iSAM's text format (isam_data_README.txt
// in the iSAM distribution; Victoria Park, cityTrees10000):
//
//   ODOMETRY i j dx dy dtheta R11 R12 R13 R22 R23 R33
//   LANDMARK i j dx dy R11 R12 R22
//
// Conventions and traps:
// - The matrix entries are the upper triangle (row-major) of the SQUARE-ROOT
//   information R (iSAM whitens its error as R e), not of the information:
//   the reader uses Omega = R^T R; the writer gives R = the upper Cholesky
//   factor of Omega (core/information.h), so a round trip reproduces R and
//   the information to rounding (about 1e-15 relative), not bit for bit.
// - ODOMETRY is the pose of j in the frame of i (our BetweenSE2Factor; iSAM
//   wraps the error differently, x_j (-) x_i - z, which agrees to first
//   order). LANDMARK is iSAM's Pose2d_Point2d_Factor: the landmark's
//   Cartesian position (dx, dy) in the robot frame, i.e. a relative-position
//   measurement (factors/relative_point2.h, g2o's EDGE_SE2_XY), not range
//   and bearing.
// - Poses and landmarks share one id space: pose ids become Pose2Key(id),
//   landmark ids (second id of LANDMARK) Point2Key(id); an id used as both
//   is an error. The file holds no values: poses are initialized from the
//   odometry (spanning tree from the lowest id), then every landmark from its
//   first observation (factors/landmark_init.h).
// - Only the 2D records are read; 3D records (EDGE3, Pose3d ...) and any
//   other tag are errors ("PATH:LINE: unknown iSAM record 'TAG'"), as are
//   malformed numbers, field counts, self-edges and singular R.
// - The writer writes the graph's SE(2) between factors as ODOMETRY and its
//   relative-point factors as LANDMARK, in FactorId order (the format holds
//   nothing else: a graph with other factors or SE(3) poses is rejected);
//   node values are not written. Atomic, shortest round-trip digits.
#ifndef SLAM_DATASETS_ISAM_IO_H_
#define SLAM_DATASETS_ISAM_IO_H_

#include <string>
#include <string_view>

#include "core/graph.h"
#include "datasets/g2o_io.h"

namespace slam {

bool ReadIsam(const std::string& path, const GraphReadOptions& options,
              Graph* graph, GraphReadReport* report, std::string* error);
bool ReadIsamFromText(const std::string& name, std::string_view text,
                      const GraphReadOptions& options, Graph* graph,
                      GraphReadReport* report, std::string* error);
bool WriteIsam(const std::string& path, const Graph& graph, std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_ISAM_IO_H_
