// Alignment of an estimated trajectory onto a reference.
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
#ifndef SLAM_CORE_METRICS_ALIGNMENT_H_
#define SLAM_CORE_METRICS_ALIGNMENT_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/lie.h"
#include "core/metrics/matrix_pose.h"

namespace slam {

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

}  // namespace slam

#endif  // SLAM_CORE_METRICS_ALIGNMENT_H_
