// Tests of the pose factors (factors/between_se2.h, between_se3.h,
// prior_se2.h, prior_se3.h, built through factors/pose_factors.h):
//   * Jacobians against numeric differentiation with ceres::GradientChecker,
//     in the tangent space of the SE(2)/SE(3) manifolds;
//   * residual values against an independent hand computation of g2o's error
//     e = t2v(Z^-1 X_i^-1 X_j) with homogeneous matrices (SE(3): translation
//     and quaternion vector part with w >= 0), whitened so that
//     |r|^2 = e^T Omega e and r = L^T e;
//   * zero residual at the measurement, quaternion sign invariance;
//   * the builders' bookkeeping and their rejection of bad information.
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/gradient_checker.h"
#include "core/graph.h"
#include "core/information.h"
#include "core/lie.h"
#include "core/manifolds.h"
#include "factors/between_se2.h"
#include "factors/between_se3.h"
#include "factors/pose_factors.h"
#include "factors/prior_se2.h"
#include "factors/prior_se3.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

using Rng = ::slam::testing::TestRng;

// ---------------------------------------------------------------------------
// Independent reference: homogeneous matrices.

Eigen::Matrix3d Homogeneous2(const Pose2& p) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(p.theta).toRotationMatrix();
  m.topRightCorner<2, 1>() = p.t;
  return m;
}

Eigen::Matrix4d Homogeneous3(const Pose3& p) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = p.q.toRotationMatrix();
  m.topRightCorner<3, 1>() = p.t;
  return m;
}

// g2o's SE2::toVector of a homogeneous transform.
Eigen::Vector3d T2V2(const Eigen::Matrix3d& m) {
  return Eigen::Vector3d(m(0, 2), m(1, 2), std::atan2(m(1, 0), m(0, 0)));
}

// g2o's toVectorMQT: translation, quaternion vector part with w >= 0.
Vector6d T2V3(const Eigen::Matrix4d& m) {
  Eigen::Quaterniond q(Eigen::Matrix3d(m.topLeftCorner<3, 3>()));
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  Vector6d e;
  e << m.topRightCorner<3, 1>(), q.vec();
  return e;
}

Eigen::Vector3d G2oErrorBetweenSE2(const Pose2& xi, const Pose2& xj,
                                   const Pose2& z) {
  return T2V2(Homogeneous2(z).inverse() * Homogeneous2(xi).inverse() *
              Homogeneous2(xj));
}

Eigen::Vector3d G2oErrorPriorSE2(const Pose2& x, const Pose2& z) {
  return T2V2(Homogeneous2(z).inverse() * Homogeneous2(x));
}

Vector6d G2oErrorBetweenSE3(const Pose3& xi, const Pose3& xj, const Pose3& z) {
  return T2V3(Homogeneous3(z).inverse() * Homogeneous3(xi).inverse() *
              Homogeneous3(xj));
}

Vector6d G2oErrorPriorSE3(const Pose3& x, const Pose3& z) {
  return T2V3(Homogeneous3(z).inverse() * Homogeneous3(x));
}

// Upper-triangular L^T with L L^T = information, computed here.
Eigen::MatrixXd ReferenceSqrt(const Eigen::MatrixXd& information) {
  Eigen::LLT<Eigen::MatrixXd> llt(information);
  return llt.matrixL().transpose();
}

Eigen::VectorXd Evaluate(const ceres::CostFunction& cost,
                         const std::vector<const double*>& params) {
  Eigen::VectorXd r(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(params.data(), r.data(), nullptr));
  return r;
}

// A small perturbation of a pose, for measurements close to (but not at)
// the relative pose of the nodes.
Pose2 Perturb(const Pose2& p, Rng* rng, double scale) {
  return p * Pose2(scale * rng->Normal(), scale * rng->Normal(),
                   scale * rng->Normal());
}

Pose3 Perturb(const Pose3& p, Rng* rng, double scale) {
  const Eigen::Vector3d phi =
      scale * Eigen::Vector3d(rng->Normal(), rng->Normal(), rng->Normal());
  return p * Pose3(scale * Eigen::Vector3d(rng->Normal(), rng->Normal(),
                                           rng->Normal()),
                   QuaternionExp<double>(phi));
}

Pose3 NegatedQuaternion(const Pose3& p) {
  Pose3 out = p;
  out.q.coeffs() = -out.q.coeffs();
  return out;
}

// Relative precision for the gradient checker (Ridders' extrapolation is
// accurate to ~1e-10 here).
constexpr double kGradientPrecision = 1e-7;

// Numeric differentiation options for the gradient checker. Ridders' first
// step is 2^5 times the initial step, i.e. 0.32 |x| with Ceres' default of
// 1e-2: that would cross the wrap of the angle error (SE(2)) or the w >= 0
// sign flip (SE(3)) far from them. 1e-4 keeps every probe within ~0.01 rad.
ceres::NumericDiffOptions NumericOptions() {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  return options;
}

// ---------------------------------------------------------------------------
// Builders.

TEST(PoseFactorBuildersTest, StoreTypeKeysMeasurementAndInformation) {
  Rng rng(1);
  std::string error;
  {
    const Pose2 z = rng.RandomPose2();
    const Eigen::Matrix3d info = rng.ScaledInformation(3);
    Factor f;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(3), Pose2Key(7), z, info, &f, &error))
        << error;
    EXPECT_EQ(f.type, FactorType::kBetweenSE2);
    ASSERT_EQ(f.keys.size(), 2u);
    EXPECT_EQ(f.keys[0], Pose2Key(3));
    EXPECT_EQ(f.keys[1], Pose2Key(7));
    EXPECT_EQ(f.measurement, Eigen::Vector3d(z.t.x(), z.t.y(), z.theta));
    EXPECT_EQ(f.information, Eigen::MatrixXd(info));
    ASSERT_NE(f.cost, nullptr);
    EXPECT_EQ(f.cost->num_residuals(), 3);
    EXPECT_EQ(f.cost->parameter_block_sizes(), (std::vector<int32_t>{3, 3}));
    EXPECT_EQ(f.loss, nullptr);
  }
  {
    const Pose2 z = rng.RandomPose2();
    Factor f;
    ASSERT_TRUE(
        MakePriorSE2(Pose2Key(2), z, rng.ScaledInformation(3), &f, &error));
    EXPECT_EQ(f.type, FactorType::kPriorSE2);
    EXPECT_EQ(f.keys, std::vector<Key>{Pose2Key(2)});
    EXPECT_EQ(f.cost->parameter_block_sizes(), (std::vector<int32_t>{3}));
  }
  {
    const Pose3 z = rng.RandomPose3();
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z, info, &f, &error));
    EXPECT_EQ(f.type, FactorType::kBetweenSE3);
    ASSERT_EQ(f.measurement.size(), 7);
    EXPECT_EQ(f.measurement.head<3>(), z.t);
    EXPECT_EQ(f.measurement.tail<4>(), z.q.coeffs());  // x, y, z, w.
    EXPECT_EQ(f.information, Eigen::MatrixXd(info));
    EXPECT_EQ(f.cost->num_residuals(), 6);
    EXPECT_EQ(f.cost->parameter_block_sizes(), (std::vector<int32_t>{7, 7}));
    const Pose3 back = MeasurementPose3(f);
    EXPECT_LT((back.t - z.t).norm(), 1e-15);
    EXPECT_LT(back.q.angularDistance(z.q), 1e-15);
  }
  {
    Factor f;
    ASSERT_TRUE(MakePriorSE3(Pose3Key(4), rng.RandomPose3(),
                             rng.ScaledInformation(6), &f, &error));
    EXPECT_EQ(f.type, FactorType::kPriorSE3);
    EXPECT_EQ(f.cost->parameter_block_sizes(), (std::vector<int32_t>{7}));
  }
}

TEST(PoseFactorBuildersTest, RejectBadInformation) {
  Eigen::Matrix3d indefinite = Eigen::Matrix3d::Identity();
  indefinite(2, 2) = -1.0;
  Eigen::Matrix3d asymmetric = Eigen::Matrix3d::Identity();
  asymmetric(0, 1) = 0.5;
  Eigen::Matrix3d nan = Eigen::Matrix3d::Identity();
  nan(1, 1) = std::nan("");
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  for (const Eigen::Matrix3d& bad : {indefinite, asymmetric, nan, zero}) {
    Factor f;
    std::string error;
    EXPECT_FALSE(
        MakeBetweenSE2(Pose2Key(0), Pose2Key(1), Pose2(), bad, &f, &error));
    EXPECT_NE(error.find("positive definite"), std::string::npos) << error;
    error.clear();
    EXPECT_FALSE(MakePriorSE2(Pose2Key(0), Pose2(), bad, &f, &error));
    EXPECT_FALSE(error.empty());
  }
  Matrix6d bad6 = Matrix6d::Identity();
  bad6(5, 5) = -1e-3;
  Factor f;
  std::string error;
  EXPECT_FALSE(
      MakeBetweenSE3(Pose3Key(0), Pose3Key(1), Pose3(), bad6, &f, &error));
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_FALSE(MakePriorSE3(Pose3Key(0), Pose3(), bad6, &f, &error));
  EXPECT_FALSE(error.empty());
}

// ---------------------------------------------------------------------------
// Between SE(2).

TEST(BetweenSE2FactorTest, ResidualIsWhitenedG2oError) {
  Rng rng(2);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 xi = rng.RandomPose2();
    const Pose2 xj = rng.RandomPose2();
    // Half the measurements far from the relative pose, half close to it.
    const Pose2 z = trial % 2 == 0 ? rng.RandomPose2(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.1);
    const Eigen::Matrix3d info = rng.ScaledInformation(3);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), z, info, &f, &error));
    const std::vector<double> vi = Pose2Value(xi), vj = Pose2Value(xj);
    const Eigen::VectorXd r = Evaluate(*f.cost, {vi.data(), vj.data()});
    const Eigen::Vector3d e = G2oErrorBetweenSE2(xi, xj, z);
    if (std::abs(e[2]) > M_PI - 1e-9) continue;  // atan2 vs wrap at +-pi.
    const double chi2 = e.dot(info * e);
    EXPECT_NEAR(r.squaredNorm(), chi2, 1e-9 * std::max(1.0, chi2));
    const Eigen::VectorXd expected_r = ReferenceSqrt(info) * e;
    EXPECT_LT((r - expected_r).norm(), 1e-9 * std::max(1.0, expected_r.norm()));
  }
}

TEST(BetweenSE2FactorTest, ErrorComponentsInMeasurementFrame) {
  // A hand-worked case: X_i = (1, 0, pi/2), X_j = (1, 2, pi/2), so X_i^-1 X_j
  // = (2, 0, 0); Z = (1, 0, pi/2): Z^-1 (2, 0, 0) = (0, -1, -pi/2).
  Factor f;
  std::string error;
  ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), Pose2(1, 0, M_PI / 2),
                             Eigen::Matrix3d::Identity(), &f, &error));
  const double xi[3] = {1.0, 0.0, M_PI / 2};
  const double xj[3] = {1.0, 2.0, M_PI / 2};
  const Eigen::VectorXd r = Evaluate(*f.cost, {xi, xj});
  EXPECT_NEAR(r[0], 0.0, 1e-15);
  EXPECT_NEAR(r[1], -1.0, 1e-15);
  EXPECT_NEAR(r[2], -M_PI / 2, 1e-15);
}

TEST(BetweenSE2FactorTest, AngleErrorIsWrapped) {
  Factor f;
  std::string error;
  ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), Pose2(0, 0, 3.0),
                             Eigen::Matrix3d::Identity(), &f, &error));
  const double xi[3] = {0.0, 0.0, 3.0};
  const double xj[3] = {0.0, 0.0, -3.0};  // Relative angle 2pi - 6.
  const Eigen::VectorXd r = Evaluate(*f.cost, {xi, xj});
  EXPECT_NEAR(r[2], NormalizeAngle(-6.0 - 3.0), 1e-14);
  EXPECT_GE(r[2], -M_PI);
  EXPECT_LT(r[2], M_PI);
}

TEST(BetweenSE2FactorTest, ZeroAtTheMeasurement) {
  Rng rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose2 xi = rng.RandomPose2();
    const Pose2 z = rng.RandomPose2(5.0);
    const Pose2 xj = xi * z;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), z,
                               rng.ScaledInformation(3), &f, &error));
    const std::vector<double> vi = Pose2Value(xi), vj = Pose2Value(xj);
    EXPECT_LT(Evaluate(*f.cost, {vi.data(), vj.data()}).norm(), 1e-10);
  }
}

TEST(BetweenSE2FactorTest, JacobiansMatchNumericInTangentSpace) {
  Rng rng(4);
  const SE2Manifold se2;
  const std::vector<const ceres::Manifold*> manifolds = {&se2, &se2};
  const ceres::NumericDiffOptions numeric_options = NumericOptions();
  int probed = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 xi = rng.RandomPose2();
    const Pose2 xj = rng.RandomPose2();
    const Pose2 z = trial % 2 == 0 ? rng.RandomPose2(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.2);
    // Keep away from the wrap of the angle error, where the residual jumps.
    if (std::abs(G2oErrorBetweenSE2(xi, xj, z)[2]) > M_PI - 0.1) continue;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), z,
                               rng.ScaledInformation(3), &f, &error));
    ceres::GradientChecker checker(f.cost.get(), &manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    const std::vector<double> vi = Pose2Value(xi), vj = Pose2Value(xj);
    const double* params[2] = {vi.data(), vj.data()};
    EXPECT_TRUE(checker.Probe(params, kGradientPrecision, &results))
        << results.error_log;
    ++probed;
  }
  EXPECT_GT(probed, 80);
}

// ---------------------------------------------------------------------------
// Prior SE(2).

TEST(PriorSE2FactorTest, ResidualIsWhitenedG2oError) {
  Rng rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 x = rng.RandomPose2();
    const Pose2 z = trial % 2 == 0 ? rng.RandomPose2() : Perturb(x, &rng, 0.1);
    const Eigen::Matrix3d info = rng.ScaledInformation(3);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakePriorSE2(Pose2Key(0), z, info, &f, &error));
    const std::vector<double> v = Pose2Value(x);
    const Eigen::VectorXd r = Evaluate(*f.cost, {v.data()});
    const Eigen::Vector3d e = G2oErrorPriorSE2(x, z);
    if (std::abs(e[2]) > M_PI - 1e-9) continue;
    const double chi2 = e.dot(info * e);
    EXPECT_NEAR(r.squaredNorm(), chi2, 1e-9 * std::max(1.0, chi2));
    EXPECT_LT((r - ReferenceSqrt(info) * e).norm(),
              1e-9 * std::max(1.0, r.norm()));
  }
}

TEST(PriorSE2FactorTest, ZeroAtTheMeasurementAndJacobians) {
  Rng rng(6);
  const SE2Manifold se2;
  const std::vector<const ceres::Manifold*> manifolds = {&se2};
  const ceres::NumericDiffOptions numeric_options = NumericOptions();
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 z = rng.RandomPose2();
    const Pose2 x = trial % 2 == 0 ? rng.RandomPose2() : Perturb(z, &rng, 0.3);
    Factor f;
    std::string error;
    ASSERT_TRUE(
        MakePriorSE2(Pose2Key(0), z, rng.ScaledInformation(3), &f, &error));
    const std::vector<double> vz = Pose2Value(z);
    EXPECT_LT(Evaluate(*f.cost, {vz.data()}).norm(), 1e-12);
    if (std::abs(G2oErrorPriorSE2(x, z)[2]) > M_PI - 0.1) continue;
    ceres::GradientChecker checker(f.cost.get(), &manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    const std::vector<double> v = Pose2Value(x);
    const double* params[1] = {v.data()};
    EXPECT_TRUE(checker.Probe(params, kGradientPrecision, &results))
        << results.error_log;
  }
}

// Evaluates `analytic` and `reference` (two parameter blocks on `manifold`)
// and expects the same residual and the same tangent-space Jacobians
// (ambient Jacobian times the manifold's PlusJacobian).
void ExpectSameTangentEvaluation(const ceres::CostFunction& analytic,
                                 const ceres::CostFunction& reference,
                                 const double* const* params,
                                 const ceres::Manifold& manifold,
                                 const std::string& what) {
  using RowMajor =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int rows = analytic.num_residuals();
  const int ambient = manifold.AmbientSize();
  Eigen::VectorXd r[2] = {Eigen::VectorXd(rows), Eigen::VectorXd(rows)};
  RowMajor j[2][2];
  const ceres::CostFunction* functions[2] = {&analytic, &reference};
  for (int f = 0; f < 2; ++f) {
    double* ptrs[2];
    for (int k = 0; k < 2; ++k) {
      j[f][k].resize(rows, ambient);
      ptrs[k] = j[f][k].data();
    }
    ASSERT_TRUE(functions[f]->Evaluate(params, r[f].data(), ptrs)) << what;
  }
  EXPECT_LT((r[0] - r[1]).norm(), 1e-12 * std::max(1.0, r[1].norm())) << what;
  for (int k = 0; k < 2; ++k) {
    RowMajor plus(ambient, manifold.TangentSize());
    manifold.PlusJacobian(params[k], plus.data());
    const Eigen::MatrixXd t_an = j[0][k] * plus;
    const Eigen::MatrixXd t_ref = j[1][k] * plus;
    EXPECT_LT((t_an - t_ref).norm(), 1e-10 * std::max(1.0, t_ref.norm()))
        << what << " block " << k << "\nanalytic\n"
        << t_an << "\nreference\n"
        << t_ref;
  }
}

// Create() is analytic (BetweenSE2CostFunction); the functor's automatic
// differentiation is the reference: same residual and Jacobians over the
// stored (x, y, theta) at random poses (both wrap the angle error alike).
TEST(BetweenSE2FactorTest, AnalyticJacobiansMatchAutoDiff) {
  Rng rng(13);
  const SE2Manifold se2;
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 xi = rng.RandomPose2();
    const Pose2 xj = rng.RandomPose2();
    const Pose2 z = trial % 2 == 0 ? rng.RandomPose2()
                                   : Perturb(xi.Inverse() * xj, &rng, 0.3);
    const Eigen::Matrix3d sqrt_info = ReferenceSqrt(rng.ScaledInformation(3));
    const Eigen::Vector3d m(z.t.x(), z.t.y(), z.theta);
    std::unique_ptr<ceres::CostFunction> analytic(
        BetweenSE2Factor::Create(m, sqrt_info));
    std::unique_ptr<ceres::CostFunction> autodiff(
        BetweenSE2Factor::CreateAutoDiff(m, sqrt_info));
    const std::vector<double> vi = Pose2Value(xi), vj = Pose2Value(xj);
    const double* params[2] = {vi.data(), vj.data()};
    ExpectSameTangentEvaluation(*analytic, *autodiff, params, se2,
                                "trial " + std::to_string(trial));
  }
}

// ---------------------------------------------------------------------------
// Between SE(3).

TEST(BetweenSE3FactorTest, ResidualIsWhitenedG2oError) {
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose3 xi = rng.RandomPose3();
    const Pose3 xj = rng.RandomPose3();
    const Pose3 z = trial % 2 == 0 ? rng.RandomPose3(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.2);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z, info, &f, &error));
    const std::vector<double> vi = Pose3Value(xi), vj = Pose3Value(xj);
    const Eigen::VectorXd r = Evaluate(*f.cost, {vi.data(), vj.data()});
    const Vector6d e = G2oErrorBetweenSE3(xi, xj, z);
    const double chi2 = e.dot(info * e);
    EXPECT_NEAR(r.squaredNorm(), chi2, 1e-9 * std::max(1.0, chi2));
    EXPECT_LT((r - ReferenceSqrt(info) * e).norm(),
              1e-9 * std::max(1.0, r.norm()));
  }
}

TEST(BetweenSE3FactorTest, RotationErrorIsHalfAngleQuaternionVector) {
  // Pure rotation error of angle a about n: e = (0, sin(a/2) n).
  const Eigen::Vector3d n = Eigen::Vector3d(1, -2, 0.5).normalized();
  for (double a : {0.1, 1.0, 2.5, 3.0}) {
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), Pose3(),
                               Matrix6d::Identity(), &f, &error));
    const Pose3 xj(Eigen::Vector3d::Zero(),
                   Eigen::Quaterniond(Eigen::AngleAxisd(a, n)));
    const std::vector<double> vi = Pose3Value(Pose3()), vj = Pose3Value(xj);
    const Eigen::VectorXd r = Evaluate(*f.cost, {vi.data(), vj.data()});
    EXPECT_LT(r.head<3>().norm(), 1e-15);
    EXPECT_LT((r.tail<3>() - std::sin(a / 2) * n).norm(), 1e-14) << a;
  }
  // Beyond pi the shorter rotation is used (w >= 0): a = 2pi - b about n is
  // b about -n.
  Factor f;
  std::string error;
  ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), Pose3(),
                             Matrix6d::Identity(), &f, &error));
  const Pose3 xj(Eigen::Vector3d::Zero(),
                 Eigen::Quaterniond(Eigen::AngleAxisd(2 * M_PI - 0.4, n)));
  const std::vector<double> vi = Pose3Value(Pose3()), vj = Pose3Value(xj);
  const Eigen::VectorXd r = Evaluate(*f.cost, {vi.data(), vj.data()});
  EXPECT_LT((r.tail<3>() + std::sin(0.2) * n).norm(), 1e-14);
}

TEST(BetweenSE3FactorTest, ZeroAtTheMeasurement) {
  Rng rng(8);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose3 xi = rng.RandomPose3();
    const Pose3 z = rng.RandomPose3(5.0);
    const Pose3 xj = xi * z;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z,
                               rng.ScaledInformation(6), &f, &error));
    const std::vector<double> vi = Pose3Value(xi), vj = Pose3Value(xj);
    EXPECT_LT(Evaluate(*f.cost, {vi.data(), vj.data()}).norm(), 1e-9);
  }
}

TEST(BetweenSE3FactorTest, QuaternionSignInvariance) {
  Rng rng(9);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 xi = rng.RandomPose3();
    const Pose3 xj = rng.RandomPose3();
    const Pose3 z = trial % 2 == 0 ? rng.RandomPose3(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.2);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f, f_neg;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z, info, &f, &error));
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), NegatedQuaternion(z),
                               info, &f_neg, &error));
    const std::vector<double> vi = Pose3Value(xi), vj = Pose3Value(xj);
    const std::vector<double> ni = Pose3Value(NegatedQuaternion(xi));
    const std::vector<double> nj = Pose3Value(NegatedQuaternion(xj));
    const Eigen::VectorXd r = Evaluate(*f.cost, {vi.data(), vj.data()});
    const double tol = 1e-11 * std::max(1.0, r.norm());
    EXPECT_LT((Evaluate(*f.cost, {ni.data(), vj.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f.cost, {vi.data(), nj.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f.cost, {ni.data(), nj.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f_neg.cost, {vi.data(), vj.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f_neg.cost, {ni.data(), nj.data()}) - r).norm(), tol);
  }
}

// Skips configurations where the error quaternion has w close to 0: there
// the w >= 0 sign choice flips and the residual jumps (as in g2o).
bool SafeForNumericDiff(const Vector6d& e) {
  return e.tail<3>().squaredNorm() < 1.0 - 0.05 * 0.05;
}

// Create() is analytic (BetweenSE3CostFunction); the functor's automatic
// differentiation is the reference: same residual, same tangent-space
// Jacobians (J_ambient times the manifold's PlusJacobian), at random poses,
// large rotations and negated quaternions included (only the w = 0 flip of
// the error quaternion, where the residual jumps, is left out).
TEST(BetweenSE3FactorTest, AnalyticJacobiansMatchAutoDiff) {
  Rng rng(12);
  const SE3Manifold se3;
  for (int trial = 0; trial < 200; ++trial) {
    Pose3 xi = rng.RandomPose3();
    Pose3 xj = rng.RandomPose3();
    if (trial % 3 == 1) xi = NegatedQuaternion(xi);
    if (trial % 5 == 2) xj = NegatedQuaternion(xj);
    const Pose3 z = trial % 2 == 0 ? rng.RandomPose3(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.3);
    const Vector6d e = G2oErrorBetweenSE3(xi, xj, z);
    if (e.tail<3>().squaredNorm() > 1.0 - 1e-6) continue;
    const Matrix6d sqrt_info = ReferenceSqrt(rng.ScaledInformation(6));
    std::unique_ptr<ceres::CostFunction> analytic(
        BetweenSE3Factor::Create(z.t, z.q, sqrt_info));
    std::unique_ptr<ceres::CostFunction> autodiff(
        BetweenSE3Factor::CreateAutoDiff(z.t, z.q, sqrt_info));
    const std::vector<double> vi = Pose3Value(xi), vj = Pose3Value(xj);
    const double* params[2] = {vi.data(), vj.data()};
    ExpectSameTangentEvaluation(*analytic, *autodiff, params, se3,
                                "trial " + std::to_string(trial));
  }
}

TEST(BetweenSE3FactorTest, JacobiansMatchNumericInTangentSpace) {
  Rng rng(10);
  const SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3, &se3};
  const ceres::NumericDiffOptions numeric_options = NumericOptions();
  int probed = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 xi = rng.RandomPose3();
    const Pose3 xj = rng.RandomPose3();
    const Pose3 z = trial % 2 == 0 ? rng.RandomPose3(5.0)
                                   : Perturb(xi.Inverse() * xj, &rng, 0.3);
    if (!SafeForNumericDiff(G2oErrorBetweenSE3(xi, xj, z))) continue;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z,
                               rng.ScaledInformation(6), &f, &error));
    ceres::GradientChecker checker(f.cost.get(), &manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    const std::vector<double> vi = Pose3Value(xi), vj = Pose3Value(xj);
    const double* params[2] = {vi.data(), vj.data()};
    EXPECT_TRUE(checker.Probe(params, kGradientPrecision, &results))
        << results.error_log;
    ++probed;
    // With the quaternions negated the tangent-space Jacobians are the same.
    const std::vector<double> ni = Pose3Value(NegatedQuaternion(xi));
    const std::vector<double> nj = Pose3Value(NegatedQuaternion(xj));
    const double* neg_params[2] = {ni.data(), nj.data()};
    ceres::GradientChecker::ProbeResults neg_results;
    EXPECT_TRUE(checker.Probe(neg_params, kGradientPrecision, &neg_results))
        << neg_results.error_log;
    for (int k = 0; k < 2; ++k) {
      EXPECT_LT(
          (neg_results.local_jacobians[k] - results.local_jacobians[k]).norm(),
          1e-9 * std::max(1.0, results.local_jacobians[k].norm()));
    }
  }
  EXPECT_GT(probed, 60);
}

// Tangent-space Jacobian of a cost function with respect to block `k` by
// central differences through the manifold's Plus (independent of
// GradientChecker, whose residual-consistency test is meaningless at an
// exactly zero residual).
Eigen::MatrixXd NumericTangentJacobian(const ceres::CostFunction& cost,
                                       std::vector<std::vector<double>> values,
                                       const ceres::Manifold& manifold, int k) {
  const int m = cost.num_residuals();
  const int n = manifold.TangentSize();
  Eigen::MatrixXd jac(m, n);
  const std::vector<double> base = values[k];
  const double h = 1e-6;
  for (int c = 0; c < n; ++c) {
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd r_plus(m), r_minus(m);
    for (int sign : {1, -1}) {
      delta[c] = sign * h;
      EXPECT_TRUE(manifold.Plus(base.data(), delta.data(), values[k].data()));
      std::vector<const double*> params;
      for (const auto& v : values) params.push_back(v.data());
      EXPECT_TRUE(cost.Evaluate(
          params.data(), sign > 0 ? r_plus.data() : r_minus.data(), nullptr));
    }
    jac.col(c) = (r_plus - r_minus) / (2 * h);
  }
  return jac;
}

// Analytic tangent-space Jacobian: ambient Jacobian times PlusJacobian.
Eigen::MatrixXd AnalyticTangentJacobian(
    const ceres::CostFunction& cost,
    const std::vector<std::vector<double>>& values,
    const ceres::Manifold& manifold, int k) {
  const int m = cost.num_residuals();
  std::vector<const double*> params;
  for (const auto& v : values) params.push_back(v.data());
  std::vector<
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
      ambient;
  std::vector<double*> jac_ptrs;
  for (const auto& v : values) {
    ambient.emplace_back(m, static_cast<int>(v.size()));
  }
  for (auto& a : ambient) jac_ptrs.push_back(a.data());
  Eigen::VectorXd r(m);
  EXPECT_TRUE(cost.Evaluate(params.data(), r.data(), jac_ptrs.data()));
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> plus(
      manifold.AmbientSize(), manifold.TangentSize());
  EXPECT_TRUE(manifold.PlusJacobian(values[k].data(), plus.data()));
  return ambient[k] * plus;
}

TEST(BetweenSE3FactorTest, JacobiansAtTheMeasurement) {
  // At zero error (the case every converged graph is near).
  Rng rng(11);
  const SE3Manifold se3;
  for (int trial = 0; trial < 20; ++trial) {
    const Pose3 xi = rng.RandomPose3();
    const Pose3 z = rng.RandomPose3(5.0);
    const Pose3 xj = xi * z;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(1), z,
                               rng.ScaledInformation(6), &f, &error));
    const std::vector<std::vector<double>> values = {Pose3Value(xi),
                                                     Pose3Value(xj)};
    for (int k = 0; k < 2; ++k) {
      const Eigen::MatrixXd numeric =
          NumericTangentJacobian(*f.cost, values, se3, k);
      const Eigen::MatrixXd analytic =
          AnalyticTangentJacobian(*f.cost, values, se3, k);
      EXPECT_LT((numeric - analytic).norm(), 1e-6 * analytic.norm())
          << "block " << k << "\nnumeric\n"
          << numeric << "\nanalytic\n"
          << analytic;
    }
  }
}

TEST(BetweenSE2FactorTest, JacobiansAtTheMeasurement) {
  Rng rng(15);
  const SE2Manifold se2;
  for (int trial = 0; trial < 20; ++trial) {
    const Pose2 xi = rng.RandomPose2();
    const Pose2 z = rng.RandomPose2(5.0);
    const Pose2 xj = xi * z;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeBetweenSE2(Pose2Key(0), Pose2Key(1), z,
                               rng.ScaledInformation(3), &f, &error));
    const std::vector<std::vector<double>> values = {Pose2Value(xi),
                                                     Pose2Value(xj)};
    for (int k = 0; k < 2; ++k) {
      const Eigen::MatrixXd numeric =
          NumericTangentJacobian(*f.cost, values, se2, k);
      const Eigen::MatrixXd analytic =
          AnalyticTangentJacobian(*f.cost, values, se2, k);
      EXPECT_LT((numeric - analytic).norm(), 1e-6 * analytic.norm())
          << "block " << k;
    }
  }
}

// ---------------------------------------------------------------------------
// Prior SE(3).

TEST(PriorSE3FactorTest, ResidualIsWhitenedG2oError) {
  Rng rng(12);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose3 x = rng.RandomPose3();
    const Pose3 z = trial % 2 == 0 ? rng.RandomPose3() : Perturb(x, &rng, 0.2);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakePriorSE3(Pose3Key(0), z, info, &f, &error));
    const std::vector<double> v = Pose3Value(x);
    const Eigen::VectorXd r = Evaluate(*f.cost, {v.data()});
    const Vector6d e = G2oErrorPriorSE3(x, z);
    const double chi2 = e.dot(info * e);
    EXPECT_NEAR(r.squaredNorm(), chi2, 1e-9 * std::max(1.0, chi2));
    EXPECT_LT((r - ReferenceSqrt(info) * e).norm(),
              1e-9 * std::max(1.0, r.norm()));
  }
}

TEST(PriorSE3FactorTest, ZeroAtMeasurementSignInvarianceAndJacobians) {
  Rng rng(13);
  const SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3};
  const ceres::NumericDiffOptions numeric_options = NumericOptions();
  int probed = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 z = rng.RandomPose3();
    const Pose3 x = trial % 2 == 0 ? rng.RandomPose3() : Perturb(z, &rng, 0.3);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f, f_neg;
    std::string error;
    ASSERT_TRUE(MakePriorSE3(Pose3Key(0), z, info, &f, &error));
    ASSERT_TRUE(
        MakePriorSE3(Pose3Key(0), NegatedQuaternion(z), info, &f_neg, &error));
    const std::vector<double> vz = Pose3Value(z),
                              vzn = Pose3Value(NegatedQuaternion(z));
    EXPECT_LT(Evaluate(*f.cost, {vz.data()}).norm(), 1e-10);
    EXPECT_LT(Evaluate(*f.cost, {vzn.data()}).norm(), 1e-10);

    const std::vector<double> v = Pose3Value(x),
                              vn = Pose3Value(NegatedQuaternion(x));
    const Eigen::VectorXd r = Evaluate(*f.cost, {v.data()});
    const double tol = 1e-11 * std::max(1.0, r.norm());
    EXPECT_LT((Evaluate(*f.cost, {vn.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f_neg.cost, {v.data()}) - r).norm(), tol);
    EXPECT_LT((Evaluate(*f_neg.cost, {vn.data()}) - r).norm(), tol);

    if (!SafeForNumericDiff(G2oErrorPriorSE3(x, z))) continue;
    ceres::GradientChecker checker(f.cost.get(), &manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    const double* params[1] = {v.data()};
    EXPECT_TRUE(checker.Probe(params, kGradientPrecision, &results))
        << results.error_log;
    ++probed;
  }
  EXPECT_GT(probed, 60);
}

// ---------------------------------------------------------------------------
// Through the graph: chi2 is the sum of e^T Omega e.

TEST(GraphFactorTest, Chi2SumsFactorErrorsAndRejectsBadFactors) {
  Rng rng(14);
  Graph graph;
  std::vector<Pose3> poses;
  for (int i = 0; i < 4; ++i) {
    poses.push_back(rng.RandomPose3());
    ASSERT_NE(graph.AddNode(Pose3Key(i), Pose3Value(poses.back())), nullptr);
  }
  double expected = 0.0;
  std::string error;
  for (int i = 0; i + 1 < 4; ++i) {
    const Pose3 z = Perturb(poses[i].Inverse() * poses[i + 1], &rng, 0.1);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f;
    ASSERT_TRUE(
        MakeBetweenSE3(Pose3Key(i), Pose3Key(i + 1), z, info, &f, &error));
    ASSERT_GE(graph.AddFactor(f), 0);
    const Vector6d e = G2oErrorBetweenSE3(poses[i], poses[i + 1], z);
    expected += e.dot(info * e);
  }
  {
    const Pose3 z = Perturb(poses[0], &rng, 0.1);
    const Matrix6d info = rng.ScaledInformation(6);
    Factor f;
    ASSERT_TRUE(MakePriorSE3(Pose3Key(0), z, info, &f, &error));
    ASSERT_GE(graph.AddFactor(f), 0);
    const Vector6d e = G2oErrorPriorSE3(poses[0], z);
    expected += e.dot(info * e);
  }
  EXPECT_NEAR(graph.Chi2(), expected, 1e-9 * expected);
  // Without loss functions the robust chi2 is the chi2.
  EXPECT_NEAR(graph.RobustChi2(), expected, 1e-9 * expected);

  // Unknown node, and a factor whose block sizes do not match the nodes.
  Factor to_missing;
  ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(99), Pose3(),
                             Matrix6d::Identity(), &to_missing, &error));
  EXPECT_EQ(graph.AddFactor(to_missing), -1);
  ASSERT_NE(graph.AddNode(Pose2Key(0), {0.0, 0.0, 0.0}), nullptr);
  Factor wrong_kind;
  ASSERT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose2Key(0), Pose3(),
                             Matrix6d::Identity(), &wrong_kind, &error));
  EXPECT_EQ(graph.AddFactor(wrong_kind), -1);
  EXPECT_EQ(graph.NumFactors(), 4u);
}

// Removing nodes goes through the node -> factor index: the factors left
// and the index agree with a brute-force recount after every change.
TEST(GraphFactorTest, RemovingNodesKeepsTheFactorIndexExact) {
  Graph graph;
  std::string error;
  for (int i = 0; i < 6; ++i) {
    ASSERT_NE(graph.AddNode(Pose3Key(i), Pose3Value(Pose3())), nullptr);
  }
  auto between = [&](int i, int j) {
    Factor f;
    EXPECT_TRUE(MakeBetweenSE3(Pose3Key(i), Pose3Key(j), Pose3(),
                               Matrix6d::Identity(), &f, &error));
    return graph.AddFactor(f);
  };
  for (int i = 0; i + 1 < 6; ++i) ASSERT_GE(between(i, i + 1), 0);
  const FactorId chord = between(0, 3);
  ASSERT_GE(between(2, 5), 0);
  auto check_index = [&]() {
    for (const auto& [key, node] : graph.nodes()) {
      std::vector<FactorId> expected;
      for (const auto& [id, factor] : graph.factors()) {
        if (std::find(factor.keys.begin(), factor.keys.end(), key) !=
            factor.keys.end()) {
          expected.push_back(id);
        }
      }
      EXPECT_EQ(graph.FactorsOf(key), expected) << key.ToString();
    }
  };
  check_index();
  EXPECT_EQ(graph.FactorsOf(Pose3Key(0)).size(), 2u);
  EXPECT_TRUE(graph.RemoveFactor(chord));
  EXPECT_FALSE(graph.RemoveFactor(chord));
  check_index();
  // Two removed nodes sharing a factor, one absent key.
  EXPECT_EQ(graph.RemoveNodes({Pose3Key(2), Pose3Key(3), Pose3Key(99)}), 2u);
  EXPECT_EQ(graph.NumFactors(), 2u);  // 0-1 and 4-5 are left.
  EXPECT_TRUE(graph.FactorsOf(Pose3Key(2)).empty());
  check_index();
  EXPECT_TRUE(graph.RemoveNode(Pose3Key(5)));
  EXPECT_FALSE(graph.RemoveNode(Pose3Key(5)));
  EXPECT_EQ(graph.NumFactors(), 1u);
  check_index();
  // New factors after removals are indexed too.
  ASSERT_GE(between(1, 4), 0);
  check_index();
}

}  // namespace
}  // namespace slam
