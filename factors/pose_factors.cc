#include "factors/pose_factors.h"

#include "core/information.h"
#include "factors/between_se2.h"
#include "factors/between_se3.h"
#include "factors/prior_se2.h"
#include "factors/prior_se3.h"

namespace slam {
namespace {

bool Whitening(const Eigen::MatrixXd& information, Eigen::MatrixXd* sqrt_info,
               std::string* error) {
  if (!SqrtInformation(information, sqrt_info)) {
    *error = "information matrix is not symmetric positive definite";
    return false;
  }
  return true;
}

}  // namespace

bool MakeBetweenSE2(const Key& i, const Key& j, const Pose2& z_ij,
                    const Eigen::Matrix3d& information, Factor* factor,
                    std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  const Eigen::Vector3d z(z_ij.t.x(), z_ij.t.y(), z_ij.theta);
  factor->type = FactorType::kBetweenSE2;
  factor->keys = {i, j};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(BetweenSE2Factor::Create(z, sqrt_info));
  return true;
}

bool MakePriorSE2(const Key& i, const Pose2& z_pose,
                  const Eigen::Matrix3d& information, Factor* factor,
                  std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  const Eigen::Vector3d z(z_pose.t.x(), z_pose.t.y(), z_pose.theta);
  factor->type = FactorType::kPriorSE2;
  factor->keys = {i};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(PriorSE2Factor::Create(z, sqrt_info));
  return true;
}

namespace {
Eigen::VectorXd Pose3Vector(const Pose3& p) {
  Eigen::VectorXd v(7);
  v << p.t, p.q.coeffs();
  return v;
}
}  // namespace

bool MakeBetweenSE3(const Key& i, const Key& j, const Pose3& z_ij,
                    const Eigen::Matrix<double, 6, 6>& information,
                    Factor* factor, std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  factor->type = FactorType::kBetweenSE3;
  factor->keys = {i, j};
  factor->measurement = Pose3Vector(z_ij);
  factor->information = information;
  factor->cost.reset(BetweenSE3Factor::Create(z_ij.t, z_ij.q, sqrt_info));
  return true;
}

bool MakePriorSE3(const Key& i, const Pose3& z,
                  const Eigen::Matrix<double, 6, 6>& information,
                  Factor* factor, std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  factor->type = FactorType::kPriorSE3;
  factor->keys = {i};
  factor->measurement = Pose3Vector(z);
  factor->information = information;
  factor->cost.reset(PriorSE3Factor::Create(z.t, z.q, sqrt_info));
  return true;
}

}  // namespace slam
