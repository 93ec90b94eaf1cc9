// Tests of the information-matrix helpers (core/information.h): the square
// root used for whitening, the positive-definiteness test, and the repair of
// indefinite matrices.
#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "core/information.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

Eigen::MatrixXd RandomPD(std::mt19937* gen, int n, double spread) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd q(n, n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) q(r, c) = normal(*gen);
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(q);
  const Eigen::MatrixXd orth = qr.householderQ();
  std::uniform_real_distribution<double> u(0.0, spread);
  Eigen::VectorXd values(n);
  for (int i = 0; i < n; ++i) values[i] = std::pow(10.0, u(*gen));
  const Eigen::MatrixXd m = orth * values.asDiagonal() * orth.transpose();
  return 0.5 * (m + m.transpose());
}

double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(SqrtInformationTest, GivesUpperTriangularTransposedFactor) {
  std::mt19937 gen(1);
  for (int n : {1, 2, 3, 6, 9}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::MatrixXd info = RandomPD(&gen, n, 4.0);
      Eigen::MatrixXd lt;
      ASSERT_TRUE(SqrtInformation(info, &lt));
      ASSERT_EQ(lt.rows(), n);
      ASSERT_EQ(lt.cols(), n);
      // Upper triangular with a positive diagonal: lt = L^T.
      for (int r = 0; r < n; ++r) {
        EXPECT_GT(lt(r, r), 0.0);
        for (int c = 0; c < r; ++c) EXPECT_EQ(lt(r, c), 0.0);
      }
      const Eigen::MatrixXd l = lt.transpose();
      EXPECT_LT(RelativeDifference(l * l.transpose(), info), 1e-13);
      // So |L^T e|^2 = e^T I e.
      const Eigen::VectorXd e = Eigen::VectorXd::Random(n);
      EXPECT_NEAR((lt * e).squaredNorm(), e.dot(info * e),
                  1e-12 * e.dot(info * e));
    }
  }
}

TEST(SqrtInformationTest, RejectsNonPositiveDefinite) {
  Eigen::MatrixXd lt;
  Eigen::Matrix3d indefinite;
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;
  EXPECT_FALSE(SqrtInformation(indefinite, &lt));
  EXPECT_FALSE(SqrtInformation(Eigen::MatrixXd::Zero(3, 3), &lt));
  EXPECT_FALSE(SqrtInformation(Eigen::MatrixXd(), &lt));
}

TEST(IsPositiveDefiniteTest, AcceptsPositiveDefinite) {
  std::mt19937 gen(2);
  for (int n : {1, 3, 6}) {
    for (int trial = 0; trial < 20; ++trial) {
      EXPECT_TRUE(IsPositiveDefinite(RandomPD(&gen, n, 6.0)));
    }
  }
  EXPECT_TRUE(IsPositiveDefinite(Eigen::MatrixXd::Identity(6, 6)));
  EXPECT_TRUE(IsPositiveDefinite(1e-8 * Eigen::MatrixXd::Identity(3, 3)));
  EXPECT_TRUE(IsPositiveDefinite(1e8 * Eigen::MatrixXd::Identity(3, 3)));
  // Symmetric to rounding (as after a text round trip).
  Eigen::Matrix3d nearly;
  nearly << 4, 1, 0.5, 1 + 1e-15, 3, 0.2, 0.5, 0.2, 2;
  EXPECT_TRUE(IsPositiveDefinite(nearly));
}

TEST(IsPositiveDefiniteTest, RejectsNonSymmetric) {
  Eigen::Matrix3d m;
  m << 4, 1, 0, 0, 3, 0, 0, 0, 2;  // PD lower triangle, not symmetric.
  EXPECT_FALSE(IsPositiveDefinite(m));
  Eigen::Matrix3d slight = Eigen::Matrix3d::Identity() * 100.0;
  slight(0, 1) = 1e-3;
  EXPECT_FALSE(IsPositiveDefinite(slight));
  EXPECT_FALSE(IsPositiveDefinite(Eigen::MatrixXd::Identity(3, 4)));
}

TEST(IsPositiveDefiniteTest, RejectsIndefiniteAndSemidefinite) {
  Eigen::Matrix3d indefinite;
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;  // Eigenvalues 3, -1, 1.
  EXPECT_FALSE(IsPositiveDefinite(indefinite));
  Eigen::Matrix2d negative = -Eigen::Matrix2d::Identity();
  EXPECT_FALSE(IsPositiveDefinite(negative));
  Eigen::Matrix2d singular;
  singular << 1, 1, 1, 1;
  EXPECT_FALSE(IsPositiveDefinite(singular));
  EXPECT_FALSE(IsPositiveDefinite(Eigen::MatrixXd::Zero(6, 6)));
  // A 6x6 with one slightly negative eigenvalue (as printed files have).
  std::mt19937 gen(3);
  Eigen::MatrixXd m = RandomPD(&gen, 6, 3.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
  Eigen::VectorXd values = eig.eigenvalues();
  values[0] = -1e-6 * values.maxCoeff();
  m = eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
  m = 0.5 * (m + m.transpose());
  EXPECT_FALSE(IsPositiveDefinite(m));
  EXPECT_FALSE(IsPositiveDefinite(Eigen::MatrixXd()));
}

TEST(IsPositiveDefiniteTest, RejectsNonFinite) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(IsPositiveDefinite(m));
  m = Eigen::Matrix3d::Identity();
  m(0, 2) = m(2, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(IsPositiveDefinite(m));
  m = Eigen::Matrix3d::Identity();
  m(2, 2) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(IsPositiveDefinite(m));
}

TEST(NearestPositiveDefiniteTest, LeavesPositiveDefiniteUnchanged) {
  std::mt19937 gen(4);
  for (int n : {1, 3, 6}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::MatrixXd m = RandomPD(&gen, n, 6.0);
      const Eigen::MatrixXd repaired = NearestPositiveDefinite(m);
      EXPECT_LT(RelativeDifference(repaired, m), 1e-12);
      EXPECT_TRUE(IsPositiveDefinite(repaired));
      EXPECT_EQ(repaired, repaired.transpose());
    }
  }
  const Eigen::MatrixXd diag =
      Eigen::Vector3d(1e4, 1.0, 40.0).asDiagonal().toDenseMatrix();
  EXPECT_LT(RelativeDifference(NearestPositiveDefinite(diag), diag), 1e-12);
}

TEST(NearestPositiveDefiniteTest, RepairsIndefiniteToCloseMatrix) {
  std::mt19937 gen(5);
  for (int n : {2, 3, 6}) {
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::MatrixXd m = RandomPD(&gen, n, 3.0);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
      Eigen::VectorXd values = eig.eigenvalues();
      // One or two eigenvalues slightly negative (rounding in a file).
      values[0] = -1e-4 * values.maxCoeff();
      if (n > 2 && trial % 2 == 0) values[1] = -2e-5 * values.maxCoeff();
      m = eig.eigenvectors() * values.asDiagonal() *
          eig.eigenvectors().transpose();
      m = 0.5 * (m + m.transpose());
      ASSERT_FALSE(IsPositiveDefinite(m));
      const Eigen::MatrixXd repaired = NearestPositiveDefinite(m);
      EXPECT_TRUE(IsPositiveDefinite(repaired));
      Eigen::MatrixXd lt;
      EXPECT_TRUE(SqrtInformation(repaired, &lt));
      // Close: the distance is the size of the clamped negative part.
      EXPECT_LT(RelativeDifference(repaired, m), 2e-4);
      // And no farther than necessary (Frobenius-nearest up to the floor).
      double negative_part = 0.0;
      for (int i = 0; i < n; ++i) {
        if (values[i] < 0) negative_part += values[i] * values[i];
      }
      EXPECT_LT((repaired - m).norm(),
                std::sqrt(negative_part) + 1e-8 * values.maxCoeff());
    }
  }
  // A non-symmetric input is symmetrized.
  Eigen::Matrix2d asym;
  asym << 2, 0.5, 0.3, 1;
  const Eigen::MatrixXd fixed = NearestPositiveDefinite(asym);
  EXPECT_TRUE(IsPositiveDefinite(fixed));
  EXPECT_NEAR(fixed(0, 1), 0.4, 1e-12);
  EXPECT_NEAR(fixed(1, 0), 0.4, 1e-12);
  // A matrix without a positive eigenvalue is not a rounding problem: it is
  // returned symmetrized and still not positive definite (documented).
  Eigen::Matrix2d negative;
  negative << -2, 0.2, 0.4, -1;
  const Eigen::MatrixXd not_fixed = NearestPositiveDefinite(negative);
  EXPECT_FALSE(IsPositiveDefinite(not_fixed));
  EXPECT_NEAR(not_fixed(0, 1), 0.3, 1e-15);
  EXPECT_NEAR(not_fixed(1, 0), 0.3, 1e-15);
  EXPECT_FALSE(
      IsPositiveDefinite(NearestPositiveDefinite(Eigen::MatrixXd::Zero(3, 3))));
}

}  // namespace
}  // namespace slam
