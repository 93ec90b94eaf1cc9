#include "factors/inertial_factors.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "core/information.h"
#include "factors/bias_random_walk.h"
#include "factors/euclidean_prior.h"
#include "factors/imu_factor.h"
#include "factors/position_factor.h"

namespace slam {
namespace {

bool Whitening(const Eigen::MatrixXd& information, Eigen::MatrixXd* sqrt_info,
               std::string* error) {
  if (!information.allFinite() || !SqrtInformation(information, sqrt_info)) {
    *error = "information matrix is not symmetric positive definite";
    return false;
  }
  return true;
}

}  // namespace

bool SqrtInformationFromCovariance(const Eigen::MatrixXd& covariance,
                                   Eigen::MatrixXd* sqrt_information) {
  if (covariance.rows() != covariance.cols() || !covariance.allFinite() ||
      !IsPositiveDefinite(covariance)) {
    return false;
  }
  Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success) return false;
  const int n = static_cast<int>(covariance.rows());
  *sqrt_information = llt.matrixL().solve(Eigen::MatrixXd::Identity(n, n));
  return sqrt_information->allFinite();
}

bool AddInertialState(Graph* graph, int64_t id, TimeNs stamp,
                      const NavState& state, const ImuBias& bias) {
  const Key keys[3] = {Pose3Key(id), VelocityKey(id), ImuBiasKey(id)};
  for (const Key& key : keys) {
    if (graph->HasNode(key)) return false;
  }
  const Eigen::Vector3d& v = state.velocity;
  const std::vector<double> values[3] = {
      Pose3Value(state.pose),
      {v.x(), v.y(), v.z()},
      std::vector<double>(bias.data(), bias.data() + 6)};
  for (int k = 0; k < 3; ++k) {
    Node* node = graph->AddNode(keys[k], values[k]);
    node->stamp = stamp;
    node->has_stamp = true;
  }
  return true;
}

bool GetInertialState(const Graph& graph, int64_t id, NavState* state,
                      ImuBias* bias) {
  const Node* pose = graph.FindNode(Pose3Key(id));
  const Node* velocity = graph.FindNode(VelocityKey(id));
  const Node* b = graph.FindNode(ImuBiasKey(id));
  if (pose == nullptr || velocity == nullptr || b == nullptr) return false;
  state->pose = NodePose3(*pose);
  state->velocity = Eigen::Map<const Eigen::Vector3d>(velocity->value.data());
  *bias = Eigen::Map<const ImuBias>(b->value.data());
  return true;
}

bool MakeImuFactor(const Key& pose_i, const Key& vel_i, const Key& bias_i,
                   const Key& pose_j, const Key& vel_j,
                   const PreintegratedImu& pim, Factor* factor,
                   std::string* error) {
  if (pim.num_samples() == 0) {
    *error = "IMU factor without any integrated reading";
    return false;
  }
  Eigen::MatrixXd sqrt_info;
  if (!SqrtInformationFromCovariance(pim.covariance(), &sqrt_info)) {
    *error = "IMU preintegration covariance is not positive definite";
    return false;
  }
  factor->type = FactorType::kImu;
  factor->keys = {pose_i, vel_i, bias_i, pose_j, vel_j};
  factor->measurement.resize(11);
  factor->measurement << pim.delta_q().coeffs(), pim.delta_v(), pim.delta_p(),
      pim.delta_t();
  factor->information = sqrt_info.transpose() * sqrt_info;
  factor->cost.reset(ImuFactor::CreateAnalytic(pim, sqrt_info));
  return true;
}

bool MakeBiasRandomWalk(const Key& bias_i, const Key& bias_j,
                        const ImuNoise& noise, double dt, Factor* factor,
                        std::string* error) {
  if (!(dt > 0.0) || !std::isfinite(dt) || !noise.IsValid()) {
    *error = "bias random walk needs dt > 0 and positive noise densities";
    return false;
  }
  Eigen::Matrix<double, 6, 1> sigma;
  const double sg = noise.gyro_random_walk * std::sqrt(dt);
  const double sa = noise.accel_random_walk * std::sqrt(dt);
  sigma << sg, sg, sg, sa, sa, sa;
  factor->type = FactorType::kBiasRandomWalk;
  factor->keys = {bias_i, bias_j};
  factor->measurement = Eigen::VectorXd::Zero(6);
  factor->information = sigma.cwiseInverse().cwiseAbs2().asDiagonal();
  const Eigen::Matrix<double, 6, 6> sqrt_info =
      sigma.cwiseInverse().asDiagonal();
  factor->cost.reset(BiasRandomWalkFactor::Create(sqrt_info));
  return true;
}

bool MakePositionFactor(const Key& pose, const Eigen::Vector3d& z,
                        const Eigen::Matrix3d& information,
                        const Eigen::Vector3d& lever_arm, Factor* factor,
                        std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  factor->type = FactorType::kPosition;
  factor->keys = {pose};
  factor->measurement.resize(6);
  factor->measurement << z, lever_arm;
  factor->information = information;
  factor->cost.reset(PositionFactor::Create(z, lever_arm, sqrt_info));
  return true;
}

namespace {

template <int N>
bool MakeEuclideanPrior(FactorType type, const Key& key,
                        const Eigen::Matrix<double, N, 1>& z,
                        const Eigen::Matrix<double, N, N>& information,
                        Factor* factor, std::string* error) {
  Eigen::MatrixXd sqrt_info;
  if (!Whitening(information, &sqrt_info, error)) return false;
  factor->type = type;
  factor->keys = {key};
  factor->measurement = z;
  factor->information = information;
  factor->cost.reset(EuclideanPriorFactor<N>::Create(z, sqrt_info));
  return true;
}

}  // namespace

bool MakePriorVelocity(const Key& velocity, const Eigen::Vector3d& z,
                       const Eigen::Matrix3d& information, Factor* factor,
                       std::string* error) {
  return MakeEuclideanPrior<3>(FactorType::kPriorVelocity, velocity, z,
                               information, factor, error);
}

bool MakePriorBias(const Key& bias, const ImuBias& z,
                   const Eigen::Matrix<double, 6, 6>& information,
                   Factor* factor, std::string* error) {
  return MakeEuclideanPrior<6>(FactorType::kPriorBias, bias, z, information,
                               factor, error);
}

}  // namespace slam
