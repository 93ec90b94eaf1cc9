// Reading and writing pose graphs in the g2o text format, and the format
// dispatcher (g2o or TORO/HOG-Man, see datasets/toro_io.h).
//
// The g2o format, as far as this backend reads it (one record per line,
// whitespace-separated, '#' starts a comment, blank lines are ignored):
//
//   VERTEX_SE2 id x y theta
//   EDGE_SE2 i j dx dy dtheta I11 I12 I13 I22 I23 I33
//   EDGE_PRIOR_SE2 id x y theta I11 I12 I13 I22 I23 I33
//   VERTEX_SE3:QUAT id x y z qx qy qz qw
//   EDGE_SE3:QUAT i j x y z qx qy qz qw I11 I12 .. I16 I22 .. I66
//   EDGE_SE3_PRIOR id offset_id x y z qx qy qz qw I11 .. I66
//   PARAMS_SE3OFFSET offset_id x y z qx qy qz qw
//   FIX id [id ...]
//
// Landmarks (factors/landmark_factors.h):
//
//   VERTEX_XY id x y                              (2D point)
//   EDGE_SE2_XY pose point x y I11 I12 I22        (point in the robot frame)
//   VERTEX_TRACKXYZ id x y z                      (3D point)
//   EDGE_SE3_TRACKXYZ pose point offset_id x y z I11 I12 I13 I22 I23 I33
//       (point in the frame of the sensor at PARAMS_SE3OFFSET offset_id on
//       the pose, as g2o's EdgeSE3PointXYZ: e = (X S)^-1 l - z)
//
// and this project's tags for the factor kinds g2o has no tag for:
//
//   EDGE_SE2_RANGE_BEARING pose point range bearing I11 I12 I22
//       (information over (range, bearing), factors/range_bearing_2d.h)
//   PARAMS_STEREO id fx fy cx cy baseline
//   EDGE_SE3_STEREO camera point param_id uL uR v I11 .. I33 (6 numbers)
//   PARAMS_PINHOLE id fx fy cx cy k1 k2 p1 p2
//   EDGE_SE3_PROJECT camera point param_id u v I11 I12 I22
//       (camera pose = T_world_camera, x right, y down, z forward;
//       factors/stereo_projection.h, factors/reprojection.h)
//
// PARAMS_* records may appear anywhere in the file (GTSAM's example puts the
// offset after the edge using it); an edge naming an undeclared one, or two
// records of one kind with the same id, is an error. Landmark vertices
// without a VERTEX_XY / VERTEX_TRACKXYZ line are created and initialized
// from their observations (factors/landmark_init.h). Landmark ids have their
// own id space, as GTSAM reads g2o files (its example_with_vertices.g2o has
// VERTEX_SE3:QUAT 0 and VERTEX_TRACKXYZ 0): Point2Key/Point3Key(id). A FIX
// line names the pose with that id if there is one, else the landmark. The
// writer numbers the parameter
// records in order of first use (equal records share one id) and writes
// them first, then pose and landmark vertices, FIX lines, and all factors in
// FactorId order: read -> write -> read reproduces every value bit for bit.
//
// Conventions and traps:
// - Information matrices are given by their upper triangle, row-major. For
//   SE(2) they are over (x, y, theta) of e = t2v(Z^-1 X_i^-1 X_j), exactly
//   our BetweenSE2Factor error. For SE(3) they are over (t, qvec) of
//   E = Z^-1 X_i^-1 X_j, where qvec is the quaternion vector part (about HALF
//   the rotation angle); BetweenSE3Factor reproduces that error, so the
//   matrices are used as they are.
// - Quaternions are written x y z w (Eigen's order). Published files store
//   some that are not exactly unit length (6 printed digits): vertex and edge
//   quaternions are normalized on reading. A quaternion whose squared norm is
//   already within 2e-15 of one is kept bit for bit, so that write -> read is
//   exact (normalizing an already normalized quaternion in floating point
//   changes its last bits about one time in three).
// - SE(2) angles are wrapped to [-pi, pi) (core/conventions.h); angles
//   already in that range are kept bit for bit.
// - Vertex ids form one id space; a VERTEX_SE2 id becomes Pose2Key(id), a
//   VERTEX_SE3:QUAT id Pose3Key(id). A file mixing SE(2) and SE(3) records is
//   rejected.
// - FIX lines may appear anywhere (even before the vertices they name); they
//   are applied after the whole file is read, and a FIX of an id that no
//   record creates is an error.
// - Some published files (CSAIL, manhattan, kitti_00) have no VERTEX lines.
//   The nodes their edges reference are then created and given an initial
//   guess from the edges (InitializePoses with kSpanningTree from the fixed
//   nodes, else from the lowest id of each connected component, left at the
//   identity); report->initialized_from_edges is set. In a file that has
//   VERTEX lines, an edge naming an id without one is an error ("unknown
//   vertex id 17") unless options.allow_missing_vertices, in which case only
//   the missing nodes are initialized that way.
// - The same pair may be joined by several edges (CSAIL and kitti_00 hold
//   one edge twice): all are kept, in file order (FactorId order). An edge
//   from a node to itself is an error.
// - EDGE_SE3_PRIOR is accepted only with an identity PARAMS_SE3OFFSET (the
//   writer emits "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1" when it writes one);
//   EDGE_SE3_TRACKXYZ takes any offset.
//   EDGE_SE2_PRIOR is read as an alias of g2o's EDGE_PRIOR_SE2.
// - Unknown tags (EQUIV, ...) are skipped with one warning per tag
//   giving the number of lines, in report->warnings (nothing is printed).
// - Malformed input (bad or non-finite numbers, missing or extra fields,
//   duplicate vertex ids, self-edges, unknown ids, information matrices that
//   are not positive definite unless options.repair_information) makes the
//   reader fail with "PATH:LINE: problem"; the graph is then left empty.
//
// The writer prints every number with %.17g, so that reading the file back
// gives bit-identical values, measurements, information matrices and fixed
// flags. It writes through PATH.tmp.XXXXXX and renames it over PATH.
#ifndef SLAM_DATASETS_G2O_IO_H_
#define SLAM_DATASETS_G2O_IO_H_

#include <string>
#include <string_view>
#include <vector>

#include "core/graph.h"

namespace slam {

struct GraphReadOptions {
  // Replace information matrices that are not positive definite by the
  // nearest positive-definite matrix (core/information.h) and count them,
  // instead of failing.
  bool repair_information = false;
  // In a file that has VERTEX lines, accept edges naming ids without one:
  // create those nodes and initialize only them from the edges (spanning
  // tree), instead of failing with "unknown vertex id N".
  bool allow_missing_vertices = false;
  // Skip lines whose tag the reader does not know, with one warning per tag
  // (what g2o does), instead of failing with "PATH:LINE: unknown tag": a
  // misspelt tag must not silently drop a record.
  bool skip_unknown_tags = false;
};

struct GraphReadReport {
  int vertices = 0;  // VERTEX lines read.
  int edges = 0;     // EDGE lines read (between and prior edges).
  int fixed = 0;     // Nodes fixed by FIX lines.
  int repaired_information = 0;
  bool initialized_from_edges = false;  // Some nodes had no VERTEX line.
  int landmarks_initialized = 0;  // Points without vertex, set from edges.
  // E.g. "unknown tag 'EQUIV' (40 lines) skipped", once per tag.
  std::vector<std::string> warnings;
};

// Reads a g2o file into *graph (must be empty). On error returns false, sets
// *error to "PATH:LINE: problem" (or "PATH: problem") and leaves *graph
// empty. `report` and `error` may be null.
bool ReadG2o(const std::string& path, const GraphReadOptions& options,
             Graph* graph, GraphReadReport* report, std::string* error);

// As ReadG2o, from text already in memory; `name` is used in messages.
bool ReadG2oFromText(const std::string& name, std::string_view text,
                     const GraphReadOptions& options, Graph* graph,
                     GraphReadReport* report, std::string* error);

// Writes the graph's SE2/SE3 pose nodes (VERTEX lines, in key order), its
// landmark nodes, FIX lines for the fixed ones, and its between/prior and
// landmark/camera factors (in FactorId order) in g2o format. Other nodes and
// factors are left out. Fails on a
// graph with both SE(2) and SE(3) poses, non-finite numbers or malformed
// pose factors. Atomic: writes PATH.tmp.XXXXXX then renames; on failure no
// file is left. Numbers are printed with %.17g.
bool WriteG2o(const std::string& path, const Graph& graph, std::string* error);

// Picks the reader by content: the first tag that one format alone uses
// (VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, EDGE_SE3:QUAT, g2o prior edges, the
// g2o landmark tags, PARAMS_STEREO, PARAMS_PINHOLE -> g2o; VERTEX2, VERTEX3,
// VERTEX, EDGE, BR, EQUIV -> TORO; ODOMETRY, LANDMARK, POINT3, Constraint2,
// POSE3D_INIT -> iSAM, datasets/isam_io.h). EDGE2/EDGE3 are both TORO's
// (information) and iSAM's (square-root information): a file of such edges
// and no deciding tag (iSAM's sphere400/sphere2500/torus10000) is TORO when
// named .graph, else iSAM, with a warning in report->warnings. A file with
// no known tag is TORO when named .graph, else g2o.
bool ReadPoseGraph(const std::string& path, const GraphReadOptions& options,
                   Graph* graph, GraphReadReport* report, std::string* error);

// By extension: .graph -> WriteToro, anything else -> WriteG2o.
bool WritePoseGraph(const std::string& path, const Graph& graph,
                    std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_G2O_IO_H_
