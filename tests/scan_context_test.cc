// The Scan Context place descriptor: rotation invariance of the ring key,
// the rotation estimate of the best sector shift, and that a different
// place is farther than the same place seen rotated and a little moved.
#include "frontends/laser/scan_context.h"

#include <cmath>
#include <random>

#include "frontends/laser/scan_simulator.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

// An L-shaped room with a pillar: no rotational symmetry.
std::vector<Wall> Room() {
  std::vector<Wall> walls = {{{0, 0}, {12, 0}},  {{12, 0}, {12, 5}},
                             {{12, 5}, {5, 5}},  {{5, 5}, {5, 10}},
                             {{5, 10}, {0, 10}}, {{0, 10}, {0, 0}}};
  for (const Wall& w : RectangleWalls(8, 2, 8.6, 2.6)) walls.push_back(w);
  return walls;
}

Points2 View(const Pose2& pose, std::mt19937* rng) {
  ScanGeometry g;
  g.angle_min = -M_PI;
  g.angle_increment = M_PI / 180;
  g.num_beams = 360;
  g.max_range = 20.0;
  return RangesToPoints(SimulateScan(Room(), pose, g, 0.01, rng), g.angle_min,
                        g.angle_increment, 0.1, g.max_range);
}

TEST(ScanContextTest, RotationIsRecoveredAndPlacesAreTold) {
  std::mt19937 rng(5);
  const ScanContextOptions options;
  const Pose2 a(2.5, 2.5, 0.0);
  const ScanContext ca = MakeScanContext(View(a, &rng), options);
  // The same place, turned by 1.2 rad and moved by 0.2 m.
  const Pose2 b(2.7, 2.5, 1.2);
  const ScanContext cb = MakeScanContext(View(b, &rng), options);
  EXPECT_LT(RingKeyDistance(ca, cb), 0.05);
  double rotation = 0.0;
  const double same = ScanContextDistance(cb, ca, &rotation);
  // b's frame into a's: +1.2 rad, to one sector (6 deg).
  EXPECT_NEAR(NormalizeAngle(rotation - 1.2), 0.0, 2 * M_PI / 60);
  // Another place of the same room.
  const Pose2 c(10.0, 1.0, 0.3);
  const ScanContext cc = MakeScanContext(View(c, &rng), options);
  double other_rotation = 0.0;
  const double other = ScanContextDistance(cc, ca, &other_rotation);
  EXPECT_LT(same, 0.5 * other) << same << " " << other;
  // Empty clouds are as far as can be.
  EXPECT_EQ(ScanContextDistance(MakeScanContext({}, options), ca, &rotation),
            1.0);
}

}  // namespace
}  // namespace slam
