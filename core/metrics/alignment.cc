#include "core/metrics/alignment.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace slam {

const char* AlignmentMethodName(AlignmentMethod method) {
  switch (method) {
    case AlignmentMethod::kNone:
      return "none";
    case AlignmentMethod::kSE3:
      return "se3";
    case AlignmentMethod::kSim3:
      return "sim3";
    case AlignmentMethod::kScale:
      return "scale";
    case AlignmentMethod::kOrigin:
      return "origin";
  }
  return "?";
}

bool ParseAlignmentMethod(const std::string& name, AlignmentMethod* method) {
  for (AlignmentMethod m :
       {AlignmentMethod::kNone, AlignmentMethod::kSE3, AlignmentMethod::kSim3,
        AlignmentMethod::kScale, AlignmentMethod::kOrigin}) {
    if (name == AlignmentMethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

Pose3 Similarity3::Apply(const Pose3& pose) const {
  return Pose3(Apply(pose.t), Eigen::Quaterniond(rotation) * pose.q);
}

MatrixPose Similarity3::Apply(const MatrixPose& pose) const {
  return MatrixPose(rotation * pose.r,
                    rotation * (scale * pose.t) + translation);
}

bool UmeyamaAlignment(const std::vector<Eigen::Vector3d>& x,
                      const std::vector<Eigen::Vector3d>& y, bool with_scale,
                      Similarity3* result, std::string* error) {
  if (x.size() != y.size()) {
    *error = "alignment needs as many points in both sets";
    return false;
  }
  if (x.size() < 2) {
    *error = "alignment needs at least 2 matched positions (got " +
             std::to_string(x.size()) + ")";
    return false;
  }
  const double n = static_cast<double>(x.size());
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_y = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= n;
  mean_y /= n;
  double sigma_x = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    const Eigen::Vector3d dx = x[i] - mean_x;
    sigma_x += dx.squaredNorm();
    cov += (y[i] - mean_y) * dx.transpose();
  }
  sigma_x /= n;
  cov /= n;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] > std::numeric_limits<double>::epsilon()) ++rank;
  }
  if (rank < 2) {
    *error =
        "degenerate covariance rank (the matched positions are "
        "collinear or identical): Umeyama alignment is not possible";
    return false;
  }
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) {
    s(2, 2) = -1.0;  // Keep a proper rotation (det +1).
  }
  result->rotation = svd.matrixU() * s * svd.matrixV().transpose();
  result->scale = with_scale ? (d.asDiagonal() * s).trace() / sigma_x : 1.0;
  result->translation = mean_y - result->scale * (result->rotation * mean_x);
  return true;
}

bool ComputeAlignment(const std::vector<Pose3>& ref,
                      const std::vector<Pose3>& est, AlignmentMethod method,
                      int n_to_align, Similarity3* result, std::string* error) {
  return ComputeAlignment(ToMatrixPoses(ref), ToMatrixPoses(est), method,
                          n_to_align, result, error);
}

bool ComputeAlignment(const std::vector<MatrixPose>& ref,
                      const std::vector<MatrixPose>& est,
                      AlignmentMethod method, int n_to_align,
                      Similarity3* result, std::string* error) {
  *result = Similarity3();
  if (ref.size() != est.size()) {
    *error = "alignment needs matched trajectories of equal size";
    return false;
  }
  if (method == AlignmentMethod::kNone) return true;
  if (ref.empty()) {
    *error = "cannot align empty trajectories";
    return false;
  }
  if (method == AlignmentMethod::kOrigin) {
    // T = P_ref,0 * P_est,0^-1 (evo's se3_inverse), applied on the left.
    const MatrixPose t = ref[0] * est[0].TransposeInverse();
    result->rotation = t.r;
    result->translation = t.t;
    result->scale = 1.0;
    return true;
  }
  size_t n = est.size();
  if (n_to_align > 0) n = std::min(n, static_cast<size_t>(n_to_align));
  std::vector<Eigen::Vector3d> x(n);
  std::vector<Eigen::Vector3d> y(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = est[i].t;
    y[i] = ref[i].t;
  }
  Similarity3 umeyama;
  const bool with_scale = method != AlignmentMethod::kSE3;
  if (!UmeyamaAlignment(x, y, with_scale, &umeyama, error)) return false;
  if (method == AlignmentMethod::kScale) {
    result->scale = umeyama.scale;  // Scale only (evo -s without -a).
  } else {
    *result = umeyama;
  }
  return true;
}

std::vector<MatrixPose> ApplyAlignment(const Similarity3& transform,
                                       const std::vector<MatrixPose>& poses) {
  std::vector<MatrixPose> out;
  out.reserve(poses.size());
  for (const MatrixPose& p : poses) out.push_back(transform.Apply(p));
  return out;
}

std::vector<Pose3> ApplyAlignment(const Similarity3& transform,
                                  const std::vector<Pose3>& poses) {
  std::vector<Pose3> out;
  out.reserve(poses.size());
  for (const Pose3& p : poses) out.push_back(transform.Apply(p));
  return out;
}

}  // namespace slam
