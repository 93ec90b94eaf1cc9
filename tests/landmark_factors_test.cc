// Tests of the landmark and camera factors (factors/range_bearing_2d.h,
// relative_point2.h, relative_point3.h, stereo_projection.h, reprojection.h,
// built through factors/landmark_factors.h) and the landmark initialization
// (factors/landmark_init.h):
//   * Jacobians against numeric differentiation with ceres::GradientChecker,
//     in the tangent space of the SE(2)/SE(3) manifolds, for every factor;
//   * residuals against an independent computation (homogeneous matrices,
//     explicit projection formulas), whitened so that |r|^2 = e^T Omega e;
//   * builders' bookkeeping, measurement layouts, rejection of bad input;
//   * the initialization pass puts points where the measurements say.
#include "factors/landmark_factors.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ceres/gradient_checker.h"
#include "core/graph.h"
#include "core/lie.h"
#include "core/manifolds.h"
#include "core/optimizer.h"
#include "factors/camera_models.h"
#include "factors/landmark_init.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Rng = ::slam::testing::TestRng;
constexpr double kGradientPrecision = 1e-6;

ceres::NumericDiffOptions NumericOptions() {
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  return options;
}

Eigen::Matrix4d Homogeneous3(const Pose3& p) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = p.q.toRotationMatrix();
  m.topRightCorner<3, 1>() = p.t;
  return m;
}

// Residual of a built factor at the given values.
Eigen::VectorXd Residual(const Factor& f, const std::vector<double>& a,
                         const std::vector<double>& b) {
  const double* params[2] = {a.data(), b.data()};
  Eigen::VectorXd r(f.cost->num_residuals());
  EXPECT_TRUE(f.cost->Evaluate(params, r.data(), nullptr));
  return r;
}

// |r|^2 must equal e^T Omega e for the reference error e.
void ExpectWhitened(const Factor& f, const Eigen::VectorXd& r,
                    const Eigen::VectorXd& e) {
  const double chi2 = e.dot(f.information * e);
  EXPECT_NEAR(r.squaredNorm(), chi2, 1e-9 * (1.0 + chi2));
}

// Jacobians in the tangent spaces against Ceres' numeric differentiation
// (Ridders). Entries are compared with a tolerance relative to the largest
// entry of their block, since several entries are exactly zero analytically
// (where GradientChecker's entry-wise relative error is only noise).
void ExpectGradientsOk(const Factor& f, const ceres::Manifold* pose_manifold,
                       const std::vector<double>& a,
                       const std::vector<double>& b) {
  std::vector<const ceres::Manifold*> manifolds = {pose_manifold, nullptr};
  ceres::GradientChecker checker(f.cost.get(), &manifolds, NumericOptions());
  ceres::GradientChecker::ProbeResults results;
  const double* params[2] = {a.data(), b.data()};
  checker.Probe(params, kGradientPrecision, &results);
  ASSERT_TRUE(results.return_value) << FactorTypeName(f.type);
  ASSERT_EQ(results.local_jacobians.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const Eigen::MatrixXd& user = results.local_jacobians[k];
    const Eigen::MatrixXd& numeric = results.local_numeric_jacobians[k];
    const double scale = std::max(1e-3, numeric.cwiseAbs().maxCoeff());
    EXPECT_LE((user - numeric).cwiseAbs().maxCoeff(),
              kGradientPrecision * scale)
        << FactorTypeName(f.type) << " block " << k << "\nuser\n"
        << user << "\nnumeric\n"
        << numeric;
  }
}

// A point in front of the camera at depth 2..20 m, within a +-40 deg cone.
Eigen::Vector3d PointInFront(const Pose3& camera, Rng* rng) {
  const double z = rng->Uniform(2.0, 20.0);
  const Eigen::Vector3d p_c(rng->Uniform(-0.8, 0.8) * z,
                            rng->Uniform(-0.6, 0.6) * z, z);
  return camera * p_c;
}

std::vector<double> Vec(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

StereoCalibration KittiStereo() {
  StereoCalibration c;
  c.fx = 721.5377;
  c.fy = 721.5377;
  c.cx = 609.5593;
  c.cy = 172.854;
  c.baseline = 0.537;
  return c;
}

PinholeCalibration EurocPinhole(bool distorted) {
  PinholeCalibration c;
  c.fx = 458.654;
  c.fy = 457.296;
  c.cx = 367.215;
  c.cy = 248.375;
  if (distorted) {
    c.k1 = -0.28340811;
    c.k2 = 0.07395907;
    c.p1 = 0.00019359;
    c.p2 = 1.76187114e-05;
  }
  return c;
}

TEST(LandmarkFactorsTest, RangeBearing2ResidualAndGradients) {
  Rng rng(41);
  SE2Manifold se2;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 x = rng.RandomPose2();
    const Eigen::Vector2d l(rng.Uniform(-30, 30), rng.Uniform(-30, 30));
    const double range = rng.Uniform(0.5, 40.0);
    const double bearing = rng.Uniform(-M_PI, M_PI);
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeRangeBearing2(Pose2Key(1), Point2Key(2), range, bearing,
                                  rng.ScaledInformation(2), &f, &error))
        << error;
    EXPECT_EQ(f.type, FactorType::kRangeBearing2);
    // Reference: landmark in the robot frame by the inverse homogeneous map.
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
    h.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(x.theta).toRotationMatrix();
    h.topRightCorner<2, 1>() = x.t;
    const Eigen::Vector3d d = h.inverse() * Eigen::Vector3d(l.x(), l.y(), 1.0);
    Eigen::Vector2d e(
        std::hypot(d.x(), d.y()) - range,
        std::remainder(std::atan2(d.y(), d.x()) - bearing, 2.0 * M_PI));
    const std::vector<double> xv = Pose2Value(x), lv = {l.x(), l.y()};
    ExpectWhitened(f, Residual(f, xv, lv), e);
    ExpectGradientsOk(f, &se2, xv, lv);
  }
  // Zero at the measurement.
  Factor f;
  std::string error;
  const Pose2 x(1.0, 2.0, 0.3);
  const Eigen::Vector2d l(4.0, -1.0);
  const Eigen::Vector2d d = RotationMatrix2D(x.theta).transpose() * (l - x.t);
  ASSERT_TRUE(MakeRangeBearing2(Pose2Key(0), Point2Key(0), d.norm(),
                                std::atan2(d.y(), d.x()),
                                Eigen::Matrix2d::Identity(), &f, &error));
  EXPECT_LT(Residual(f, Pose2Value(x), {l.x(), l.y()}).norm(), 1e-12);
}

TEST(LandmarkFactorsTest, RelativePoint2ResidualAndGradients) {
  Rng rng(42);
  SE2Manifold se2;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 x = rng.RandomPose2();
    const Eigen::Vector2d l(rng.Uniform(-30, 30), rng.Uniform(-30, 30));
    const Eigen::Vector2d z(rng.Uniform(-10, 10), rng.Uniform(-10, 10));
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeRelativePoint2(Pose2Key(1), Point2Key(1), z,
                                   rng.ScaledInformation(2), &f, &error));
    EXPECT_EQ(f.type, FactorType::kRelativePoint2);
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
    h.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(x.theta).toRotationMatrix();
    h.topRightCorner<2, 1>() = x.t;
    const Eigen::Vector3d d = h.inverse() * Eigen::Vector3d(l.x(), l.y(), 1.0);
    const Eigen::Vector2d e = d.head<2>() - z;
    const std::vector<double> xv = Pose2Value(x), lv = {l.x(), l.y()};
    ExpectWhitened(f, Residual(f, xv, lv), e);
    ExpectGradientsOk(f, &se2, xv, lv);
  }
}

TEST(LandmarkFactorsTest, RelativePoint3WithOffsetResidualAndGradients) {
  Rng rng(43);
  SE3Manifold se3;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 x = rng.RandomPose3();
    const Pose3 offset = trial % 3 == 0 ? Pose3() : rng.RandomPose3(1.0);
    const Eigen::Vector3d l = rng.Normal3() * 10.0;
    const Eigen::Vector3d z = rng.Normal3() * 5.0;
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeRelativePoint3(Pose3Key(1), Point3Key(1), z, offset,
                                   rng.ScaledInformation(3), &f, &error));
    EXPECT_EQ(f.type, FactorType::kRelativePoint3);
    ASSERT_EQ(f.measurement.size(), 10);
    const Pose3 back = SensorOffsetOf(f);
    EXPECT_LT((back.t - offset.t).norm(), 1e-15);
    EXPECT_LT(back.q.angularDistance(offset.q), 1e-12);
    const Eigen::Vector4d d =
        (Homogeneous3(x) * Homogeneous3(offset)).inverse() *
        Eigen::Vector4d(l.x(), l.y(), l.z(), 1.0);
    const Eigen::Vector3d e = d.head<3>() - z;
    std::vector<double> xv = Pose3Value(x), lv = Vec(l);
    ExpectWhitened(f, Residual(f, xv, lv), e);
    ExpectGradientsOk(f, &se3, xv, lv);
  }
}

TEST(LandmarkFactorsTest, StereoResidualAndGradients) {
  Rng rng(44);
  SE3Manifold se3;
  const StereoCalibration c = KittiStereo();
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 camera = rng.RandomPose3();
    const Eigen::Vector3d l = PointInFront(camera, &rng);
    const Eigen::Vector3d z(rng.Uniform(0, 1240), rng.Uniform(0, 1240),
                            rng.Uniform(0, 370));
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeStereo(Pose3Key(0), Point3Key(0), c, z,
                           rng.ScaledInformation(3), &f, &error));
    EXPECT_EQ(f.type, FactorType::kStereo);
    EXPECT_TRUE(StereoCalibrationOf(f) == c);
    // Reference: explicit formulas in the camera frame.
    const Eigen::Vector4d p = Homogeneous3(camera).inverse() *
                              Eigen::Vector4d(l.x(), l.y(), l.z(), 1.0);
    const Eigen::Vector3d predicted(c.fx * p.x() / p.z() + c.cx,
                                    c.fx * (p.x() - c.baseline) / p.z() + c.cx,
                                    c.fy * p.y() / p.z() + c.cy);
    const std::vector<double> xv = Pose3Value(camera), lv = Vec(l);
    ExpectWhitened(f, Residual(f, xv, lv), predicted - z);
    ExpectGradientsOk(f, &se3, xv, lv);
  }
}

TEST(LandmarkFactorsTest, ReprojectionResidualAndGradients) {
  Rng rng(45);
  SE3Manifold se3;
  for (int trial = 0; trial < 100; ++trial) {
    const bool distorted = trial % 2 == 1;
    const PinholeCalibration c = EurocPinhole(distorted);
    const Pose3 camera = rng.RandomPose3();
    const Eigen::Vector3d l = PointInFront(camera, &rng);
    const Eigen::Vector2d z(rng.Uniform(0, 752), rng.Uniform(0, 480));
    Factor f;
    std::string error;
    ASSERT_TRUE(MakeReprojection(Pose3Key(0), Point3Key(0), c, z,
                                 rng.ScaledInformation(2), &f, &error));
    EXPECT_EQ(f.type, FactorType::kReprojection);
    EXPECT_TRUE(PinholeCalibrationOf(f) == c);
    const Eigen::Vector4d p = Homogeneous3(camera).inverse() *
                              Eigen::Vector4d(l.x(), l.y(), l.z(), 1.0);
    const double xn = p.x() / p.z(), yn = p.y() / p.z();
    const double r2 = xn * xn + yn * yn;
    const double radial = 1.0 + c.k1 * r2 + c.k2 * r2 * r2;
    const double xd =
        xn * radial + 2.0 * c.p1 * xn * yn + c.p2 * (r2 + 2.0 * xn * xn);
    const double yd =
        yn * radial + c.p1 * (r2 + 2.0 * yn * yn) + 2.0 * c.p2 * xn * yn;
    const Eigen::Vector2d predicted(c.fx * xd + c.cx, c.fy * yd + c.cy);
    const std::vector<double> xv = Pose3Value(camera), lv = Vec(l);
    ExpectWhitened(f, Residual(f, xv, lv), predicted - z);
    ExpectGradientsOk(f, &se3, xv, lv);
  }
}

TEST(LandmarkFactorsTest, CameraFactorsFailBehindTheCamera) {
  Factor stereo, mono;
  std::string error;
  ASSERT_TRUE(MakeStereo(Pose3Key(0), Point3Key(0), KittiStereo(),
                         Eigen::Vector3d(600, 580, 170),
                         Eigen::Matrix3d::Identity(), &stereo, &error));
  ASSERT_TRUE(MakeReprojection(Pose3Key(0), Point3Key(0), EurocPinhole(false),
                               Eigen::Vector2d(300, 200),
                               Eigen::Matrix2d::Identity(), &mono, &error));
  const std::vector<double> camera = Pose3Value(Pose3());
  const std::vector<double> behind = {0.0, 0.0, -3.0};
  const double* params[2] = {camera.data(), behind.data()};
  double r[3];
  EXPECT_FALSE(stereo.cost->Evaluate(params, r, nullptr));
  EXPECT_FALSE(mono.cost->Evaluate(params, r, nullptr));
}

TEST(LandmarkFactorsTest, BuildersRejectBadInput) {
  Factor f;
  std::string error;
  Eigen::Matrix2d not_pd;
  not_pd << 1.0, 2.0, 2.0, 1.0;
  EXPECT_FALSE(MakeRangeBearing2(Pose2Key(0), Point2Key(0), 1.0, 0.0, not_pd,
                                 &f, &error));
  EXPECT_NE(error.find("positive definite"), std::string::npos);
  EXPECT_FALSE(MakeRelativePoint2(Pose3Key(0), Point2Key(0),
                                  Eigen::Vector2d(1, 1),
                                  Eigen::Matrix2d::Identity(), &f, &error));
  EXPECT_NE(error.find("pose2"), std::string::npos) << error;
  EXPECT_FALSE(MakeRelativePoint3(Pose3Key(0), Point3Key(0),
                                  Eigen::Vector3d(NAN, 0, 0), Pose3(),
                                  Eigen::Matrix3d::Identity(), &f, &error));
  StereoCalibration bad_stereo = KittiStereo();
  bad_stereo.baseline = 0.0;
  EXPECT_FALSE(MakeStereo(Pose3Key(0), Point3Key(0), bad_stereo,
                          Eigen::Vector3d(1, 1, 1), Eigen::Matrix3d::Identity(),
                          &f, &error));
  EXPECT_NE(error.find("baseline"), std::string::npos);
  PinholeCalibration bad_pinhole = EurocPinhole(false);
  bad_pinhole.fy = -1.0;
  EXPECT_FALSE(MakeReprojection(Pose3Key(0), Point3Key(0), bad_pinhole,
                                Eigen::Vector2d(1, 1),
                                Eigen::Matrix2d::Identity(), &f, &error));
}

TEST(LandmarkFactorsTest, RemakeReproducesEveryFactor) {
  Rng rng(46);
  std::vector<Factor> factors(5);
  std::string error;
  ASSERT_TRUE(MakeRangeBearing2(Pose2Key(0), Point2Key(1), 3.0, 0.5,
                                rng.ScaledInformation(2), &factors[0], &error));
  ASSERT_TRUE(
      MakeRelativePoint2(Pose2Key(0), Point2Key(1), Eigen::Vector2d(1, 2),
                         rng.ScaledInformation(2), &factors[1], &error));
  ASSERT_TRUE(MakeRelativePoint3(
      Pose3Key(0), Point3Key(1), Eigen::Vector3d(1, 2, 3), rng.RandomPose3(1.0),
      rng.ScaledInformation(3), &factors[2], &error));
  ASSERT_TRUE(MakeStereo(Pose3Key(0), Point3Key(1), KittiStereo(),
                         Eigen::Vector3d(700, 650, 100),
                         rng.ScaledInformation(3), &factors[3], &error));
  ASSERT_TRUE(MakeReprojection(Pose3Key(0), Point3Key(1), EurocPinhole(true),
                               Eigen::Vector2d(300, 200),
                               rng.ScaledInformation(2), &factors[4], &error));
  for (const Factor& f : factors) {
    Factor copy;
    ASSERT_TRUE(RemakeLandmarkFactor(f, &copy, &error)) << error;
    EXPECT_EQ(copy.type, f.type);
    EXPECT_EQ(copy.measurement, f.measurement);
    const bool is3 = f.keys[0].kind == NodeKind::kPose3;
    const std::vector<double> pose =
        is3 ? Pose3Value(Pose3(
                  rng.Normal3() * 0.1,
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.1, rng.UnitVector()))))
            : Pose2Value(rng.RandomPose2(0.5));
    const std::vector<double> point = is3 ? std::vector<double>{0.3, -0.2, 8.0}
                                          : std::vector<double>{4.0, 1.0};
    EXPECT_EQ(Residual(copy, pose, point), Residual(f, pose, point));
  }
}

TEST(LandmarkFactorsTest, InitializationPlacesPointsFromObservations) {
  Rng rng(47);
  // 2D: range-bearing and relative observations from known poses.
  {
    Graph graph;
    const Pose2 x(2.0, -1.0, 0.7);
    graph.AddNode(Pose2Key(0), Pose2Value(x));
    const Eigen::Vector2d l1(5.0, 3.0), l2(-4.0, 6.0);
    graph.AddNode(Point2Key(1), {0.0, 0.0});
    graph.AddNode(Point2Key(2), {0.0, 0.0});
    const Eigen::Vector2d d1 =
        RotationMatrix2D(x.theta).transpose() * (l1 - x.t);
    const Eigen::Vector2d d2 =
        RotationMatrix2D(x.theta).transpose() * (l2 - x.t);
    Factor f1, f2;
    std::string error;
    ASSERT_TRUE(MakeRangeBearing2(Pose2Key(0), Point2Key(1), d1.norm(),
                                  std::atan2(d1.y(), d1.x()),
                                  Eigen::Matrix2d::Identity(), &f1, &error));
    ASSERT_TRUE(MakeRelativePoint2(Pose2Key(0), Point2Key(2), d2,
                                   Eigen::Matrix2d::Identity(), &f2, &error));
    ASSERT_GE(graph.AddFactor(f1), 0);
    ASSERT_GE(graph.AddFactor(f2), 0);
    const LandmarkInitReport report = InitializeLandmarks(&graph);
    EXPECT_EQ(report.initialized, 2);
    const std::vector<double>& v1 = graph.FindNode(Point2Key(1))->value;
    const std::vector<double>& v2 = graph.FindNode(Point2Key(2))->value;
    EXPECT_NEAR(v1[0], l1.x(), 1e-12);
    EXPECT_NEAR(v1[1], l1.y(), 1e-12);
    EXPECT_NEAR(v2[0], l2.x(), 1e-12);
    EXPECT_NEAR(v2[1], l2.y(), 1e-12);
  }
  // 3D: relative with offset, stereo and two-view monocular.
  {
    Graph graph;
    const Pose3 c0 = rng.RandomPose3(5.0);
    const Pose3 c1 = c0 * Pose3(Eigen::Vector3d(1.0, 0.2, 0.1),
                                Eigen::Quaterniond(Eigen::AngleAxisd(
                                    0.1, Eigen::Vector3d::UnitY())));
    graph.AddNode(Pose3Key(0), Pose3Value(c0));
    graph.AddNode(Pose3Key(1), Pose3Value(c1));
    const Eigen::Vector3d l = c0 * Eigen::Vector3d(0.5, -0.3, 9.0);
    for (int k = 1; k <= 3; ++k) graph.AddNode(Point3Key(k), {0.0, 0.0, 0.0});
    std::string error;
    Factor rel, st, m0, m1;
    const Pose3 offset = rng.RandomPose3(0.3);
    ASSERT_TRUE(MakeRelativePoint3(Pose3Key(0), Point3Key(1),
                                   (c0 * offset).Inverse() * l, offset,
                                   Eigen::Matrix3d::Identity(), &rel, &error));
    const StereoCalibration sc = KittiStereo();
    const Eigen::Vector3d pc = c0.Inverse() * l;
    Eigen::Vector3d stereo_uv;
    ASSERT_TRUE(ProjectStereo(sc, pc, &stereo_uv));
    ASSERT_TRUE(MakeStereo(Pose3Key(0), Point3Key(2), sc, stereo_uv,
                           Eigen::Matrix3d::Identity(), &st, &error));
    const PinholeCalibration pc_cal = EurocPinhole(true);
    Eigen::Vector2d uv0, uv1;
    ASSERT_TRUE(ProjectPinhole(pc_cal, pc, &uv0));
    ASSERT_TRUE(
        ProjectPinhole(pc_cal, Eigen::Vector3d(c1.Inverse() * l), &uv1));
    ASSERT_TRUE(MakeReprojection(Pose3Key(0), Point3Key(3), pc_cal, uv0,
                                 Eigen::Matrix2d::Identity(), &m0, &error));
    ASSERT_TRUE(MakeReprojection(Pose3Key(1), Point3Key(3), pc_cal, uv1,
                                 Eigen::Matrix2d::Identity(), &m1, &error));
    for (const Factor* f : {&rel, &st, &m0, &m1})
      ASSERT_GE(graph.AddFactor(*f), 0);
    const LandmarkInitReport report = InitializeLandmarks(&graph);
    EXPECT_EQ(report.initialized, 3);
    EXPECT_EQ(report.weak, 0);
    EXPECT_EQ(report.failed, 0);
    for (int k = 1; k <= 3; ++k) {
      const std::vector<double>& v = graph.FindNode(Point3Key(k))->value;
      EXPECT_LT((Eigen::Vector3d(v[0], v[1], v[2]) - l).norm(), 1e-6) << k;
    }
  }
}

// End to end with a known answer: noiseless observations of points from a
// ring of cameras, everything perturbed but the gauge, bundle adjustment
// brings back the true cameras and points.
void RunSyntheticBundleAdjustment(bool stereo) {
  Rng rng(stereo ? 48 : 49);
  Graph truth;
  std::vector<Pose3> cameras;
  for (int i = 0; i < 6; ++i) {
    // Cameras on a line along x, looking along +z, slightly rotated.
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(0.05 * rng.Normal(), rng.UnitVector()));
    cameras.emplace_back(Eigen::Vector3d(0.5 * i, 0.1 * rng.Normal(), 0), q);
  }
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < 40; ++j) {
    points.emplace_back(rng.Uniform(-3, 5), rng.Uniform(-2, 2),
                        rng.Uniform(4, 12));
  }
  Graph graph;
  for (int i = 0; i < 6; ++i) {
    Pose3 start = cameras[i];
    // Monocular BA has a scale gauge as well: hold two cameras.
    const bool held = i == 0 || (!stereo && i == 5);
    if (!held) {
      start =
          start *
          Pose3(rng.Normal3() * 0.05,
                Eigen::Quaterniond(Eigen::AngleAxisd(0.02, rng.UnitVector())));
    }
    graph.AddNode(Pose3Key(i), Pose3Value(start));
    graph.SetFixed(Pose3Key(i), held);
  }
  for (int j = 0; j < 40; ++j) {
    const Eigen::Vector3d p = points[j] + rng.Normal3() * 0.2;
    graph.AddNode(Point3Key(j), {p.x(), p.y(), p.z()});
  }
  const StereoCalibration sc = KittiStereo();
  const PinholeCalibration pc = EurocPinhole(true);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 40; ++j) {
      const Eigen::Vector3d p_c = cameras[i].Inverse() * points[j];
      Factor f;
      std::string error;
      if (stereo) {
        Eigen::Vector3d uv;
        ASSERT_TRUE(ProjectStereo(sc, p_c, &uv));
        ASSERT_TRUE(MakeStereo(Pose3Key(i), Point3Key(j), sc, uv,
                               Eigen::Matrix3d::Identity(), &f, &error));
      } else {
        Eigen::Vector2d uv;
        ASSERT_TRUE(ProjectPinhole(pc, p_c, &uv));
        ASSERT_TRUE(MakeReprojection(Pose3Key(i), Point3Key(j), pc, uv,
                                     Eigen::Matrix2d::Identity(), &f, &error));
      }
      ASSERT_GE(graph.AddFactor(f), 0);
    }
  }
  OptimizerOptions options;
  options.verbose = false;
  const OptimizerSummary summary = Optimize(&graph, options, nullptr);
  EXPECT_TRUE(summary.converged) << summary.termination;
  EXPECT_EQ(summary.linear_solver, "SPARSE_SCHUR");
  EXPECT_LT(CameraPixelErrors(graph).rms, 1e-6);
  for (int j = 0; j < 40; ++j) {
    const std::vector<double>& v = graph.FindNode(Point3Key(j))->value;
    EXPECT_LT((Eigen::Vector3d(v[0], v[1], v[2]) - points[j]).norm(), 1e-6)
        << j;
  }
  for (int i = 0; i < 6; ++i) {
    const Pose3 x = NodePose3(*graph.FindNode(Pose3Key(i)));
    EXPECT_LT((x.t - cameras[i].t).norm(), 1e-6) << i;
    EXPECT_LT(x.q.angularDistance(cameras[i].q), 1e-6) << i;
  }
}

TEST(LandmarkFactorsTest, StereoBundleAdjustmentRecoversTheTruth) {
  RunSyntheticBundleAdjustment(true);
}

TEST(LandmarkFactorsTest, MonocularBundleAdjustmentRecoversTheTruth) {
  RunSyntheticBundleAdjustment(false);
}

}  // namespace
}  // namespace slam
