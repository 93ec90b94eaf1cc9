// Tests of core/triangulation.h against points with a known position.
#include "core/triangulation.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "core/lie.h"
#include "gtest/gtest.h"
#include "tests/test_random.h"

namespace slam {
namespace {

using Rng = ::slam::testing::TestRng;

TEST(TriangulationTest, InvertRangeBearingRecoversThePoint) {
  Rng rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 x = rng.RandomPose2();
    const Eigen::Vector2d l(rng.Uniform(-50, 50), rng.Uniform(-50, 50));
    const Eigen::Vector2d d = RotationMatrix2D(x.theta).transpose() * (l - x.t);
    const Eigen::Vector2d back =
        InvertRangeBearing(x, d.norm(), std::atan2(d.y(), d.x()));
    EXPECT_LT((back - l).norm(), 1e-10);
  }
  // Bearing is counter-clockwise from the robot's x axis.
  const Eigen::Vector2d p =
      InvertRangeBearing(Pose2(1, 1, M_PI / 2), 2.0, M_PI / 2);
  EXPECT_NEAR(p.x(), -1.0, 1e-12);
  EXPECT_NEAR(p.y(), 1.0, 1e-12);
}

TEST(TriangulationTest, StereoRecoversThePointAndRejectsBadDisparity) {
  Rng rng(8);
  const double fx = 718.0, fy = 716.0, cx = 607.0, cy = 185.0, b = 0.54;
  for (int trial = 0; trial < 100; ++trial) {
    const Pose3 camera = rng.RandomPose3();
    const double z = rng.Uniform(1.0, 60.0);
    const Eigen::Vector3d pc(rng.Uniform(-1, 1) * z, rng.Uniform(-0.3, 0.3) * z,
                             z);
    const Eigen::Vector3d uv(fx * pc.x() / z + cx, fx * (pc.x() - b) / z + cx,
                             fy * pc.y() / z + cy);
    Eigen::Vector3d p;
    ASSERT_TRUE(TriangulateStereo(camera, fx, fy, cx, cy, b, uv, &p));
    EXPECT_LT((p - camera * pc).norm(), 1e-9 * z);
  }
  Eigen::Vector3d p(7, 7, 7);
  EXPECT_FALSE(TriangulateStereo(Pose3(), fx, fy, cx, cy, b,
                                 Eigen::Vector3d(500, 500, 100), &p));
  EXPECT_FALSE(TriangulateStereo(Pose3(), fx, fy, cx, cy, b,
                                 Eigen::Vector3d(500, 510, 100), &p));
  EXPECT_EQ(p, Eigen::Vector3d(7, 7, 7));
}

TEST(TriangulationTest, MidpointOfTwoRays) {
  Rng rng(9);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d l = rng.Normal3() * 10.0;
    const Eigen::Vector3d o1 = rng.Normal3() * 3.0;
    const Eigen::Vector3d o2 = rng.Normal3() * 3.0;
    Eigen::Vector3d p;
    // Exact rays meet at l (skip nearly parallel draws).
    if ((l - o1).normalized().cross((l - o2).normalized()).norm() < 1e-3)
      continue;
    ASSERT_TRUE(TriangulateMidpoint(o1, (l - o1) * 2.0, o2, l - o2, &p));
    EXPECT_LT((p - l).norm(), 1e-8);
  }
  // Skew rays: the midpoint of the common perpendicular.
  Eigen::Vector3d p;
  ASSERT_TRUE(TriangulateMidpoint(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
      Eigen::Vector3d(5, -3, 2), Eigen::Vector3d(0, 1, 0), &p));
  EXPECT_LT((p - Eigen::Vector3d(5, 0, 1)).norm(), 1e-12);
  // Parallel rays and points behind an origin are rejected.
  EXPECT_FALSE(TriangulateMidpoint(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1),
      Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 2), &p));
  EXPECT_FALSE(TriangulateMidpoint(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
      Eigen::Vector3d(5, -3, 2), Eigen::Vector3d(0, -1, 0), &p));
}

}  // namespace
}  // namespace slam
