// Tests of the SE(2) and SE(3) manifolds (core/manifolds.h) and the Lie
// helpers they use (core/lie.h): Ceres' generic manifold invariants at many
// random points, including angles near +-pi and quaternions near w = 0, and
// the convention written down in core/conventions.h (right / body-frame
// perturbation, translation first, full angle, theta wrapped to [-pi, pi)).
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ceres/manifold_test_utils.h"
#include "core/graph.h"
#include "core/lie.h"
#include "core/manifolds.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using ceres::Vector;
// The matchers of ceres/manifold_test_utils.h are called unqualified by
// EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD.
using ceres::HasCorrectMinusJacobianAt;
using ceres::HasCorrectPlusJacobianAt;
using ceres::HasCorrectRightMultiplyByPlusJacobianAt;
using ceres::MinusPlusIsIdentityAt;
using ceres::MinusPlusJacobianIsIdentityAt;
using ceres::PlusMinusIsIdentityAt;
using ceres::XMinusXIsZeroAt;
using ceres::XPlusZeroIsXAt;

constexpr double kTolerance = 1e-9;

using Rng = ::slam::testing::TestRng;

Vector SE2Value(double x, double y, double theta) {
  Vector v(3);
  v << x, y, theta;
  return v;
}

Vector SE3Value(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Vector v(7);
  v << t, q.coeffs();
  return v;
}

// A quaternion with w = `w` exactly (up to rounding) and a random axis; w may
// be negative (storage does not force w >= 0).
Eigen::Quaterniond QuaternionWithW(Rng* rng, double w) {
  const Eigen::Vector3d axis = rng->UnitVector() * std::sqrt(1.0 - w * w);
  return Eigen::Quaterniond(w, axis.x(), axis.y(), axis.z());
}

// Rotation angle between two unit quaternions (sign-insensitive).
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

// ---------------------------------------------------------------------------
// NormalizeAngle.

TEST(NormalizeAngleTest, WrapsIntoHalfOpenInterval) {
  const double pi = M_PI;
  const std::vector<double> inputs = {0.0,
                                      1.0,
                                      -1.0,
                                      pi,
                                      -pi,
                                      3.0 * pi,
                                      -3.0 * pi,
                                      2.0 * pi,
                                      -2.0 * pi,
                                      std::nextafter(pi, 0.0),
                                      std::nextafter(pi, 4.0),
                                      std::nextafter(-pi, 0.0),
                                      std::nextafter(-pi, -4.0),
                                      std::nextafter(3.0 * pi, 0.0),
                                      std::nextafter(-3.0 * pi, 0.0),
                                      pi - 1e-15,
                                      -pi + 1e-15,
                                      100.0,
                                      -100.0,
                                      1e6 + 0.25,
                                      7.0 * pi / 2.0};
  for (double a : inputs) {
    const double w = NormalizeAngle(a);
    EXPECT_GE(w, -pi) << "input " << a;
    EXPECT_LT(w, pi) << "input " << a;
    // Same angle: a - w is a multiple of 2 pi.
    const double k = (a - w) / (2.0 * pi);
    EXPECT_NEAR(k, std::round(k), 1e-9 * std::max(1.0, std::abs(a)))
        << "input " << a;
  }
  EXPECT_EQ(NormalizeAngle(pi), -pi);
  EXPECT_EQ(NormalizeAngle(-pi), -pi);
  EXPECT_DOUBLE_EQ(NormalizeAngle(0.5), 0.5);
  EXPECT_DOUBLE_EQ(NormalizeAngle(0.5 + 2.0 * pi), 0.5);
}

TEST(NormalizeAngleTest, RandomAnglesLandInRange) {
  Rng rng(7);
  for (int i = 0; i < 20000; ++i) {
    const double a = rng.Uniform(-20.0, 20.0);
    const double w = NormalizeAngle(a);
    ASSERT_GE(w, -M_PI) << a;
    ASSERT_LT(w, M_PI) << a;
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
}

// ---------------------------------------------------------------------------
// Quaternion Exp / Log.

TEST(QuaternionExpLogTest, ExpIsFullAngleAxisRotation) {
  Rng rng(11);
  for (int i = 0; i < 200; ++i) {
    const double angle = rng.Uniform(0.0, 3.0);
    const Eigen::Vector3d axis = rng.UnitVector();
    const Eigen::Vector3d phi = angle * axis;
    const Eigen::Quaterniond q = QuaternionExp<double>(phi);
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    EXPECT_NEAR(q.norm(), 1.0, 1e-14);
    EXPECT_LT((q.coeffs() - expected.coeffs()).norm(), 1e-14);
  }
  // Small angles go through the Taylor branch.
  for (double angle : {0.0, 1e-12, 1e-9, 1e-7, 1e-6, 2e-6}) {
    const Eigen::Vector3d axis = rng.UnitVector();
    const Eigen::Quaterniond q = QuaternionExp<double>(angle * axis);
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    EXPECT_LT((q.coeffs() - expected.coeffs()).norm(), 1e-15) << angle;
  }
}

TEST(QuaternionExpLogTest, LogInvertsExpAndPicksShortestRotation) {
  Rng rng(12);
  for (int i = 0; i < 200; ++i) {
    const double angle = rng.Uniform(0.0, M_PI - 1e-6);
    const Eigen::Vector3d phi = angle * rng.UnitVector();
    const Eigen::Quaterniond q = QuaternionExp<double>(phi);
    EXPECT_LT((QuaternionLog<double>(q) - phi).norm(), 1e-12);
    // -q is the same rotation: same Log.
    Eigen::Quaterniond neg = q;
    neg.coeffs() = -neg.coeffs();
    EXPECT_LT((QuaternionLog<double>(neg) - phi).norm(), 1e-12);
  }
  for (double angle : {0.0, 1e-12, 1e-8, 1e-6, 3e-6}) {
    const Eigen::Vector3d phi = angle * rng.UnitVector();
    EXPECT_LT((QuaternionLog<double>(QuaternionExp<double>(phi)) - phi).norm(),
              1e-18 + 1e-12 * angle);
  }
  // w = 0: a rotation by exactly pi.
  const Eigen::Quaterniond half_turn(0.0, 0.0, 0.0, 1.0);
  EXPECT_LT(
      (QuaternionLog<double>(half_turn) - Eigen::Vector3d(0, 0, M_PI)).norm(),
      1e-15);
}

// ---------------------------------------------------------------------------
// SE(2): Ceres invariants.

TEST(SE2ManifoldTest, CeresInvariantsAtRandomPoints) {
  const SE2Manifold manifold;
  Rng rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    const Vector x = SE2Value(rng.Uniform(-50, 50), rng.Uniform(-50, 50),
                              rng.Uniform(-M_PI, M_PI));
    const Vector y = SE2Value(rng.Uniform(-50, 50), rng.Uniform(-50, 50),
                              rng.Uniform(-M_PI, M_PI));
    // |dtheta| < pi so that Minus(Plus(x, d), x) = d.
    const Vector delta = SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5),
                                  rng.Uniform(-3.1, 3.1));
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
  }
}

TEST(SE2ManifoldTest, CeresInvariantsNearPlusMinusPi) {
  const SE2Manifold manifold;
  Rng rng(2);
  // The numeric Plus/Minus Jacobians of Ceres' matchers step by up to 1e-4
  // in theta, so the full macro runs 2e-3 away from the wrap point...
  for (double theta : {M_PI - 2e-3, -M_PI + 2e-3, M_PI - 0.1, -M_PI + 0.1}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Vector x = SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5), theta);
      const Vector y =
          SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5),
                   trial % 2 == 0 ? -theta : NormalizeAngle(theta - 0.01));
      const Vector delta = SE2Value(rng.Uniform(-1, 1), rng.Uniform(-1, 1),
                                    rng.Uniform(-3.1, 3.1));
      EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
    }
  }
  // ... and the Jacobian-free invariants run right at the wrap point.
  for (double theta :
       {-M_PI, std::nextafter(M_PI, 0.0), M_PI - 1e-12, -M_PI + 1e-12}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Vector x = SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5), theta);
      const Vector y = SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5),
                                trial % 2 == 0 ? -M_PI + 0.5 : M_PI - 0.5);
      const Vector delta = SE2Value(rng.Uniform(-1, 1), rng.Uniform(-1, 1),
                                    rng.Uniform(-3.1, 3.1));
      const Vector zero = Vector::Zero(3);
      EXPECT_THAT(manifold, XPlusZeroIsXAt(x, kTolerance));
      EXPECT_THAT(manifold, XMinusXIsZeroAt(x, kTolerance));
      EXPECT_THAT(manifold, MinusPlusIsIdentityAt(x, delta, kTolerance));
      EXPECT_THAT(manifold, MinusPlusIsIdentityAt(x, zero, kTolerance));
      EXPECT_THAT(manifold, PlusMinusIsIdentityAt(x, y, kTolerance));
      EXPECT_THAT(manifold, MinusPlusJacobianIsIdentityAt(x, kTolerance));
      EXPECT_THAT(manifold,
                  HasCorrectRightMultiplyByPlusJacobianAt(x, kTolerance));
      // y right at the wrap point as well: an ulp of rounding may turn -pi
      // into pi - 1 ulp (the same angle), so compare angles, not numbers.
      const Vector y_wrap = SE2Value(rng.Uniform(-5, 5), rng.Uniform(-5, 5),
                                     trial % 2 == 0 ? -M_PI : M_PI - 1e-12);
      Vector y_minus_x(3), back(3);
      ASSERT_TRUE(manifold.Minus(y_wrap.data(), x.data(), y_minus_x.data()));
      ASSERT_TRUE(manifold.Plus(x.data(), y_minus_x.data(), back.data()));
      EXPECT_LT((back.head<2>() - y_wrap.head<2>()).norm(), 1e-12);
      EXPECT_LT(std::abs(NormalizeAngle(back[2] - y_wrap[2])), 1e-12);
      EXPECT_GE(back[2], -M_PI);
      EXPECT_LT(back[2], M_PI);
    }
  }
}

// ---------------------------------------------------------------------------
// SE(2): convention.

TEST(SE2ManifoldTest, PlusMovesInBodyFrame) {
  const SE2Manifold manifold;
  const double x[3] = {1.0, 2.0, M_PI / 2.0};
  const double delta[3] = {1.0, 0.0, 0.0};
  double out[3];
  ASSERT_TRUE(manifold.Plus(x, delta, out));
  // Forward along the body x axis, which points along world +y.
  EXPECT_NEAR(out[0], 1.0, 1e-15);
  EXPECT_NEAR(out[1], 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(out[2], M_PI / 2.0);

  Rng rng(3);
  for (int i = 0; i < 100; ++i) {
    const double xi[3] = {rng.Uniform(-9, 9), rng.Uniform(-9, 9),
                          rng.Uniform(-M_PI, M_PI)};
    const double d[3] = {rng.Uniform(-2, 2), rng.Uniform(-2, 2),
                         rng.Uniform(-2, 2)};
    double o[3];
    ASSERT_TRUE(manifold.Plus(xi, d, o));
    // X [+] d = X * (d as a pose) with the translation applied first: the
    // right perturbation is t + R d_t, theta + d_theta (no SE(2) Exp).
    const Eigen::Vector2d t =
        Eigen::Vector2d(xi[0], xi[1]) +
        Eigen::Rotation2Dd(xi[2]) * Eigen::Vector2d(d[0], d[1]);
    EXPECT_NEAR(o[0], t.x(), 1e-13);
    EXPECT_NEAR(o[1], t.y(), 1e-13);
    EXPECT_NEAR(std::cos(o[2]), std::cos(xi[2] + d[2]), 1e-13);
    EXPECT_NEAR(std::sin(o[2]), std::sin(xi[2] + d[2]), 1e-13);
    // Minus expresses the difference in the body frame of x.
    double back[3];
    ASSERT_TRUE(manifold.Minus(o, xi, back));
    EXPECT_NEAR(back[0], d[0], 1e-12);
    EXPECT_NEAR(back[1], d[1], 1e-12);
    EXPECT_NEAR(back[2], d[2], 1e-12);
  }
}

TEST(SE2ManifoldTest, PlusWrapsThetaIntoHalfOpenInterval) {
  const SE2Manifold manifold;
  {
    const double x[3] = {0.0, 0.0, 3.0};
    const double d[3] = {0.0, 0.0, 1.0};
    double o[3];
    ASSERT_TRUE(manifold.Plus(x, d, o));
    EXPECT_NEAR(o[2], 4.0 - 2.0 * M_PI, 1e-15);
  }
  {
    const double x[3] = {0.0, 0.0, -3.0};
    const double d[3] = {0.0, 0.0, -1.0};
    double o[3];
    ASSERT_TRUE(manifold.Plus(x, d, o));
    EXPECT_NEAR(o[2], 2.0 * M_PI - 4.0, 1e-15);
  }
  {
    // Landing exactly on pi gives -pi.
    const double x[3] = {0.0, 0.0, M_PI / 2.0};
    const double d[3] = {0.0, 0.0, M_PI / 2.0};
    double o[3];
    ASSERT_TRUE(manifold.Plus(x, d, o));
    EXPECT_EQ(o[2], -M_PI);
  }
  Rng rng(4);
  for (int i = 0; i < 5000; ++i) {
    const double x[3] = {0.0, 0.0, rng.Uniform(-M_PI, M_PI)};
    const double d[3] = {0.0, 0.0, rng.Uniform(-2.0 * M_PI, 2.0 * M_PI)};
    double o[3];
    ASSERT_TRUE(manifold.Plus(x, d, o));
    ASSERT_GE(o[2], -M_PI);
    ASSERT_LT(o[2], M_PI);
    double m[3];
    ASSERT_TRUE(manifold.Minus(o, x, m));
    ASSERT_GE(m[2], -M_PI);
    ASSERT_LT(m[2], M_PI);
  }
}

TEST(SE2ManifoldTest, MinusAcrossTheWrapIsShort) {
  const SE2Manifold manifold;
  const double x[3] = {0.0, 0.0, M_PI - 0.05};
  const double y[3] = {0.0, 0.0, -M_PI + 0.05};
  double m[3];
  ASSERT_TRUE(manifold.Minus(y, x, m));
  EXPECT_NEAR(m[2], 0.1, 1e-14);
  ASSERT_TRUE(manifold.Minus(x, y, m));
  EXPECT_NEAR(m[2], -0.1, 1e-14);
}

// ---------------------------------------------------------------------------
// SE(3): Ceres invariants.

// y with the sign of its quaternion chosen so that q_x^-1 q_y has w >= 0:
// Minus returns the shortest rotation (angle in [0, pi]), so Plus(x, Minus(y,
// x)) reproduces y itself only for this sign, and -y otherwise (the same
// pose); see SE3ManifoldTest.PlusMinusHoldsUpToQuaternionSign.
Vector AlignedSE3Value(const Eigen::Vector3d& t, Eigen::Quaterniond qy,
                       const Eigen::Quaterniond& qx) {
  if ((qx.conjugate() * qy).w() < 0.0) qy.coeffs() = -qy.coeffs();
  return SE3Value(t, qy);
}

Vector RandomSE3Delta(Rng* rng, double max_angle) {
  Vector delta(6);
  delta.head<3>() = Eigen::Vector3d(rng->Uniform(-5, 5), rng->Uniform(-5, 5),
                                    rng->Uniform(-5, 5));
  delta.tail<3>() = rng->Uniform(0.0, max_angle) * rng->UnitVector();
  return delta;
}

Eigen::Vector3d RandomTranslation(Rng* rng) {
  return Eigen::Vector3d(rng->Uniform(-50, 50), rng->Uniform(-50, 50),
                         rng->Uniform(-50, 50));
}

TEST(SE3ManifoldTest, CeresInvariantsAtRandomPoints) {
  const SE3Manifold manifold;
  Rng rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Quaterniond qx = rng.Quaternion();
    const Vector x = SE3Value(RandomTranslation(&rng), qx);
    const Vector y =
        AlignedSE3Value(RandomTranslation(&rng), rng.Quaternion(), qx);
    // |phi| < pi so that Minus(Plus(x, d), x) = d.
    const Vector delta = RandomSE3Delta(&rng, M_PI - 1e-3);
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
  }
}

TEST(SE3ManifoldTest, CeresInvariantsNearWZeroAndNegativeW) {
  const SE3Manifold manifold;
  Rng rng(6);
  for (double w :
       {0.0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3, -0.5, -0.999, -1.0, 1.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Quaterniond qx = QuaternionWithW(&rng, w);
      const Vector x = SE3Value(RandomTranslation(&rng), qx);
      // y near the antipode of the rotation space too (relative w ~ 0).
      const Eigen::Quaterniond qy =
          trial % 2 == 0 ? rng.Quaternion()
                         : qx * QuaternionWithW(&rng, 1e-7 * (trial % 3));
      const Vector y = AlignedSE3Value(RandomTranslation(&rng), qy, qx);
      const Vector delta = RandomSE3Delta(&rng, M_PI - 1e-3);
      EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
    }
  }
}

TEST(SE3ManifoldTest, MinusPlusIsIdentityForRotationsCloseToPi) {
  const SE3Manifold manifold;
  Rng rng(8);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector x = SE3Value(RandomTranslation(&rng), rng.Quaternion());
    Vector delta = RandomSE3Delta(&rng, 1.0);
    delta.tail<3>() = (M_PI - 1e-7) * rng.UnitVector();
    EXPECT_THAT(manifold, MinusPlusIsIdentityAt(x, delta, 1e-8));
  }
}

TEST(SE3ManifoldTest, PlusMinusHoldsUpToQuaternionSign) {
  const SE3Manifold manifold;
  Rng rng(9);
  int flipped = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Quaterniond qx = rng.Quaternion();
    const Vector x = SE3Value(RandomTranslation(&rng), qx);
    const Eigen::Quaterniond qy = rng.Quaternion();  // Not sign-aligned.
    const Vector y = SE3Value(RandomTranslation(&rng), qy);
    Vector d(6), back(7);
    ASSERT_TRUE(manifold.Minus(y.data(), x.data(), d.data()));
    EXPECT_LE(d.tail<3>().norm(), M_PI + 1e-12);
    ASSERT_TRUE(manifold.Plus(x.data(), d.data(), back.data()));
    EXPECT_LT((back.head<3>() - y.head<3>()).norm(), 1e-12);
    const double same = (back.tail<4>() - y.tail<4>()).norm();
    const double opposite = (back.tail<4>() + y.tail<4>()).norm();
    EXPECT_LT(std::min(same, opposite), 1e-12);
    if (opposite < same) ++flipped;
  }
  // Both signs occur: the documented behaviour (shortest rotation) is really
  // exercised.
  EXPECT_GT(flipped, 0);
}

// ---------------------------------------------------------------------------
// SE(3): convention.

TEST(SE3ManifoldTest, TranslationDeltaIsInBodyFrame) {
  const SE3Manifold manifold;
  Rng rng(10);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Quaterniond q = rng.Quaternion();
    const Eigen::Vector3d t = RandomTranslation(&rng);
    const Vector x = SE3Value(t, q);
    const Eigen::Vector3d rho(rng.Uniform(-3, 3), rng.Uniform(-3, 3),
                              rng.Uniform(-3, 3));
    Vector delta = Vector::Zero(6);
    delta.head<3>() = rho;
    Vector out(7);
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), out.data()));
    EXPECT_LT((out.head<3>() - (t + q.toRotationMatrix() * rho)).norm(), 1e-12);
    // Rotation untouched (to rounding).
    EXPECT_LT((out.tail<4>() - q.coeffs()).norm(), 1e-15);
  }
  // A concrete case: yaw of 90 degrees, step along body x = world y.
  const Eigen::Quaterniond yaw(
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Vector x = SE3Value(Eigen::Vector3d(1, 2, 3), yaw);
  Vector delta = Vector::Zero(6);
  delta[0] = 1.0;
  Vector out(7);
  ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), out.data()));
  EXPECT_LT((out.head<3>() - Eigen::Vector3d(1, 3, 3)).norm(), 1e-15);
}

TEST(SE3ManifoldTest, RotationDeltaIsRightMultipliedFullAngle) {
  const SE3Manifold manifold;
  Rng rng(13);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Quaterniond q = rng.Quaternion();
    const Eigen::Vector3d t = RandomTranslation(&rng);
    const Vector x = SE3Value(t, q);
    const double angle = rng.Uniform(1e-3, 3.0);
    const Eigen::Vector3d axis = rng.UnitVector();
    Vector delta = Vector::Zero(6);
    delta.tail<3>() = angle * axis;
    Vector out(7);
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), out.data()));
    EXPECT_LT((out.head<3>() - t).norm(), 1e-15);
    const Eigen::Quaterniond got(out[6], out[3], out[4], out[5]);
    EXPECT_NEAR(got.norm(), 1.0, 1e-14);
    const Eigen::Quaterniond expected =
        q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
    EXPECT_LT(AngleBetween(got, expected), 1e-12);
    // Rotated by exactly |phi| (full angle, not half), about the body axis:
    // the world axis R * axis is left unchanged by the increment.
    EXPECT_NEAR(AngleBetween(got, q), angle, 1e-10);
    const Eigen::Matrix3d r_inc =
        q.toRotationMatrix().transpose() * got.toRotationMatrix();
    EXPECT_LT((r_inc * axis - axis).norm(), 1e-12);
    // Left multiplication (world frame) differs in general.
    const Eigen::Quaterniond left =
        Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) * q;
    if (AngleBetween(left, expected) > 1e-3) {
      EXPECT_GT(AngleBetween(got, left), 1e-4);
    }
  }
}

TEST(SE3ManifoldTest, PlusKeepsUnitQuaternion) {
  const SE3Manifold manifold;
  Rng rng(14);
  Vector x = SE3Value(Eigen::Vector3d::Zero(), rng.Quaternion());
  for (int i = 0; i < 1000; ++i) {
    const Vector delta = RandomSE3Delta(&rng, 3.0);
    Vector out(7);
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), out.data()));
    x = out;
  }
  EXPECT_NEAR(x.tail<4>().norm(), 1.0, 1e-14);
}

TEST(SE3ManifoldTest, MinusIsBodyFrameFullAngle) {
  const SE3Manifold manifold;
  const Eigen::Quaterniond qx(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d tx(1, -2, 0.5);
  const Eigen::Vector3d axis = Eigen::Vector3d(-1, 0.5, 2).normalized();
  const Eigen::Quaterniond qy =
      qx * Eigen::Quaterniond(Eigen::AngleAxisd(2.5, axis));
  const Eigen::Vector3d ty = tx + qx * Eigen::Vector3d(0.1, 0.2, 0.3);
  const Vector x = SE3Value(tx, qx);
  const Vector y = SE3Value(ty, qy);
  Vector d(6);
  ASSERT_TRUE(manifold.Minus(y.data(), x.data(), d.data()));
  EXPECT_LT((d.head<3>() - Eigen::Vector3d(0.1, 0.2, 0.3)).norm(), 1e-14);
  EXPECT_LT((d.tail<3>() - 2.5 * axis).norm(), 1e-12);
}

TEST(GraphManifoldTest, PoseKindsUseTheManifolds) {
  Graph graph;
  EXPECT_NE(
      dynamic_cast<const SE2Manifold*>(graph.ManifoldFor(NodeKind::kPose2)),
      nullptr);
  EXPECT_NE(
      dynamic_cast<const SE3Manifold*>(graph.ManifoldFor(NodeKind::kPose3)),
      nullptr);
  EXPECT_EQ(graph.ManifoldFor(NodeKind::kPoint3), nullptr);
  EXPECT_EQ(graph.ManifoldFor(NodeKind::kVelocity3), nullptr);
  EXPECT_EQ(TangentSize(NodeKind::kPose2), 3);
  EXPECT_EQ(TangentSize(NodeKind::kPose3), 6);
  EXPECT_EQ(AmbientSize(NodeKind::kPose3), 7);
}

}  // namespace
}  // namespace slam
