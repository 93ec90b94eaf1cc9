// Reading and writing pose graphs in the TORO / HOG-Man text format.
//
// One record per line, whitespace-separated, '#' starts a comment:
//
//   VERTEX2 id x y theta                      (alias: VERTEX)
//   EDGE2 i j dx dy dtheta I11 I12 I22 I33 I13 I23   (alias: EDGE)
//   VERTEX3 id x y z roll pitch yaw
//   EDGE3 i j x y z roll pitch yaw I11 I12 .. I16 I22 .. I66
//   FIX id [id ...]        (an extension of this backend, see below)
//
// Conventions and traps:
// - EDGE2 gives the information over (x, y, theta) -- the same error as g2o's
//   EDGE_SE2 and our BetweenSE2Factor -- but in the order
//   inf_ff inf_fs inf_ss inf_rr inf_fr inf_sr, i.e. I11 I12 I22 I33 I13 I23,
//   NOT g2o's I11 I12 I13 I22 I23 I33.
// - 3D rotations are Euler angles, R = Rz(yaw) Ry(pitch) Rx(roll) (HOG-Man's
//   RotationMatrix3). The EDGE3 information is over HOG-Man's error
//   e_h = (t_E, rpy(E)) of E = Z^-1 X_i^-1 X_j, while our BetweenSE3Factor
//   uses e = (t_E, qvec(E)) of the same E (quaternion vector part, w >= 0).
//   Linearized at the measurement (E = I), q(rpy) = qz(yaw) qy(pitch)
//   qx(roll) = (1, roll/2, pitch/2, yaw/2) + O(|rpy|^2), so qvec = J rpy with
//   J = d qvec / d rpy |_0 = I/2 exactly, and e = D^-1 e_h with
//   D = diag(1, 1, 1, 2, 2, 2). Then e_h^T Omega_h e_h = e^T (D Omega_h D) e:
//   the reader uses Omega = J^-T Omega_h J^-1 = D Omega_h D (rotation block
//   times 4, translation-rotation blocks times 2) and the writer the inverse
//   D^-1 Omega D^-1. Both are exact in floating point.
// - Vertex and edge rotations are converted to unit quaternions; a 3D file
//   written and read back reproduces rotations to about 1e-15 (Euler angles
//   are not an exact encoding of a quaternion), everything else bit for bit.
//   2D files round trip bit for bit.
// - BR pose landmark bearing range sigma_bearing sigma_range (GTSAM's
//   example.graph; field order as GTSAM's dataset.cpp reads it) becomes a
//   range-bearing factor (factors/range_bearing_2d.h) to Point2Key(landmark)
//   with information diag(1/sigma_range^2, 1/sigma_bearing^2); landmark ids
//   have their own id space (GTSAM's L(id)). The file holds no landmark values:
//   each landmark is initialized from its first observation. The writer
//   writes range-bearing factors with diagonal information as BR lines (a
//   round trip reproduces the sigmas to rounding; landmark values are not
//   written) and rejects other landmark factors.
// - EQUIV (vertex equivalence, gtsam_w100.graph) lines, like any unknown
//   tag, are skipped with one warning per tag.
// - TORO has no fixed-node record; the writer adds "FIX id" lines (which TORO
//   and HOG-Man ignore as unknown lines) and the reader applies them, so that
//   fixed flags survive a round trip. TORO has no prior edges: writing a graph
//   with prior factors fails.
// - Everything else (ids, multi-edges, self-edges, missing vertices,
//   positive definiteness, errors "PATH:LINE: problem") is as in
//   datasets/g2o_io.h.
#ifndef SLAM_DATASETS_TORO_IO_H_
#define SLAM_DATASETS_TORO_IO_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/graph.h"
#include "datasets/g2o_io.h"

namespace slam {
namespace text {
class PoseGraphBuilder;
}  // namespace text

// Reads a TORO/HOG-Man file into *graph (must be empty). On error returns
// false, sets *error to "PATH:LINE: problem" and leaves *graph empty.
bool ReadToro(const std::string& path, const GraphReadOptions& options,
              Graph* graph, GraphReadReport* report, std::string* error);

// As ReadToro, from text already in memory; `name` is used in messages.
bool ReadToroFromText(const std::string& name, std::string_view text,
                      const GraphReadOptions& options, Graph* graph,
                      GraphReadReport* report, std::string* error);

// Writes the SE2/SE3 pose nodes and between factors (VERTEX2/EDGE2 or
// VERTEX3/EDGE3) and FIX lines. Atomic like WriteG2o; numbers with %.17g.
bool WriteToro(const std::string& path, const Graph& graph, std::string* error);

// Euler angles as TORO, HOG-Man and iSAM use them: R = Rz(yaw) Ry(pitch)
// Rx(roll) (HOG-Man's RotationMatrix3, iSAM's Rot3d), and the inverse
// (pitch in [-pi/2, pi/2]).
Eigen::Quaterniond QuaternionFromRpy(double roll, double pitch, double yaw);
Eigen::Vector3d RpyFromQuaternion(const Eigen::Quaterniond& q);

// The 3D vertex record "TAG id x y z roll pitch yaw" (TORO's VERTEX3, iSAM's
// POSE3D_INIT) added to `builder`; false with *problem (a field error, for
// the caller to place) or *error (from the builder).
bool AddVertexRpy(const std::vector<std::string_view>& tokens, int64_t line,
                  text::PoseGraphBuilder* builder, std::string* problem,
                  std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_TORO_IO_H_
