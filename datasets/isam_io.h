// Reading and writing graphs in iSAM's text format (isam_data_README.txt in
// the iSAM distribution; iSAM's isam/Loader.cpp is the reference for what
// each record means). Records, one per line:
//
//   ODOMETRY i j x y theta R11 R12 R13 R22 R23 R33   (aliases EDGE2,
//                                                     Constraint2)
//   LANDMARK i l x y R11 R12 R22
//   EDGE3 i j x y z roll pitch yaw [R11 R12 .. R16 R22 .. R66]
//   POINT3 i p x y z [R11 R12 R13 R22 R23 R33]
//   POSE3D_INIT i x y z roll pitch yaw
//
// Conventions and traps:
// - The matrix entries are the upper triangle (row-major) of the SQUARE-ROOT
//   information R (iSAM whitens its error as R e), not of the information:
//   Omega_iSAM = R^T R. Without the optional entries (EDGE3, POINT3) R is
//   the identity, as in iSAM.
// - Poses and landmarks have SEPARATE id spaces (iSAM maps them with two
//   mappers): pose ids become Pose2Key/Pose3Key(id), the landmark id of
//   LANDMARK Point2Key(id), of POINT3 Point3Key(id). cityTrees10000 numbers
//   both from 0.
// - ODOMETRY is iSAM's Pose2d_Pose2d_Factor, error e_iSAM = (x_i^-1 x_j) - z
//   as vectors (translation in the frame of i, angle wrapped). Our
//   BetweenSE2Factor (g2o's EDGE_SE2) expresses the translation error in the
//   frame of z instead: e_iSAM = J e with J = diag(Rot(theta_z), 1), exactly
//   (the translation part is linear). The reader uses Omega = J^T Omega_iSAM
//   J, so the objective is iSAM's to the last bit of rounding; the writer
//   inverts it.
// - EDGE3 is iSAM's Pose3d_Pose3d_Factor, e_iSAM = vec(x_i^-1 x_j) - vec(z)
//   with vec = (x, y, z, yaw, pitch, roll), angles wrapped. The file gives
//   the angles and the rows/columns of R in the order roll, pitch, yaw (iSAM
//   reverses its internal order when it reads them; with off-diagonal
//   rotation entries iSAM's own permutation is marked as wrong in its
//   source, the reader follows the README: R over (x, y, z, roll, pitch,
//   yaw)). R = Rz(yaw) Ry(pitch) Rx(roll). Our BetweenSE3Factor's error
//   e = (t_E, qvec(E)), E = z^-1 x_i^-1 x_j, agrees to first order at E = I
//   with e_iSAM = J e, J = diag(R_z, 2 W^-1), W the matrix mapping Euler-
//   angle rates to body angular rates at z's angles (translation part
//   exact). Omega = J^T Omega_iSAM J. An edge from a higher to a lower id is
//   turned around (z^-1 between j and i with the same R), as iSAM does.
//   Measurements at pitch +-90 degrees (Euler singularity) are rejected.
// - LANDMARK / POINT3 are iSAM's Pose2d_Point2d_Factor / Pose3d_Point3d_
//   Factor: the landmark's Cartesian position in the robot frame, i.e. our
//   relative-point factors (factors/relative_point2.h, relative_point3.h),
//   whose error is the same vector difference, so Omega = Omega_iSAM.
// - POSE3D_INIT gives a pose's initial value; every other node is
//   initialized by the reader: poses from the edges (spanning tree from the
//   lowest id), then every landmark from its first observation
//   (factors/landmark_init.h). iSAM's bookkeeping records SOLVE, EDGE3_INIT,
//   POSE3D_TRUE and EDGE3_TRUE are skipped with one warning per tag. The
//   stereo records (CAMERA_STEREO, POINT_STEREO) and any other tag are
//   errors ("PATH:LINE: ..."), as are malformed numbers, field counts,
//   self-edges, a singular R and a file mixing 2D and 3D records.
// - The writer writes the 2D graph's SE(2) between factors as ODOMETRY and
//   its relative-point factors as LANDMARK, in FactorId order (a graph with
//   other factors or SE(3) poses is rejected); node values are not written.
//   R is the upper Cholesky factor of iSAM's information, so a round trip
//   reproduces the information to rounding (about 1e-15 relative). Atomic,
//   shortest round-trip digits.
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
