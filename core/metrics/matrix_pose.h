// Poses and trajectories as the evaluation (evo, the KITTI devkit) holds
// them, rotation angles and path length.
//
// Poses are used as read (MatrixPose): a KITTI file's 3x3 blocks are not
//   exactly rotations (7 significant digits), and evo and the devkit use them
//   as they are; inverses are evo's se3_inverse [R^T | -R^T t] (the devkit's
//   KITTI metric: the true matrix inverse). A rotation is extracted only
//   where an angle is needed, as evo does (scipy Rotation.from_matrix: the
//   quaternion of Markley's four-branch method, normalized; RotationAngleDeg).
//   TUM/EuRoC quaternions are normalized and turned into matrices as evo
//   (transformations.quaternion_matrix).
#ifndef SLAM_CORE_METRICS_MATRIX_POSE_H_
#define SLAM_CORE_METRICS_MATRIX_POSE_H_

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/conventions.h"
#include "core/lie.h"
#include "core/trajectory.h"

namespace slam {

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

// Rotation angle of a unit quaternion, radians in [0, pi].
double RotationAngle(const Eigen::Quaterniond& q);
// Rotation angle of a 3x3 matrix that is a rotation up to rounding, as evo's
// so3_log_angle (scipy: Markley's quaternion, normalized, then |rotvec|).
double RotationAngleOfMatrix(const Eigen::Matrix3d& m);

// Sum of distances between consecutive positions.
double PathLength(const std::vector<MatrixPose>& poses);
double PathLength(const std::vector<Pose3>& poses);

}  // namespace slam

#endif  // SLAM_CORE_METRICS_MATRIX_POSE_H_
