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

// Points at radius r in the sectors listed (60 sectors), turned by
// `shift` sectors.
Points2 Arcs(const std::vector<int>& sectors, double r, int shift) {
  Points2 points;
  for (int s : sectors) {
    const double phi = 2.0 * M_PI * (s + shift + 0.5) / 60.0;
    points.emplace_back(r * std::cos(phi), r * std::sin(phi));
  }
  return points;
}

// The ring key sees how a ring's occupancy is spread, not only how much is
// occupied: one wall ahead and two walls on either side occupy the same
// number of cells of each ring, but are told apart; the key of a turned
// view is the same.
TEST(ScanContextTest, RingKeyTellsTheSpreadOfTheOccupancyRotationInvariantly) {
  const ScanContextOptions options;
  std::vector<int> block, split;
  for (int s = 0; s < 10; ++s) block.push_back(s);
  for (int s = 0; s < 5; ++s) {
    split.push_back(s);
    split.push_back(30 + s);
  }
  const ScanContext one = MakeScanContext(Arcs(block, 5.0, 0), options);
  const ScanContext turned = MakeScanContext(Arcs(block, 5.0, 17), options);
  const ScanContext two = MakeScanContext(Arcs(split, 5.0, 0), options);
  EXPECT_LT(RingKeyDistance(one, turned), 1e-10);
  EXPECT_GT(RingKeyDistance(one, two), 0.01);
  ScanContextOptions occupancy_only = options;
  occupancy_only.key_harmonics = 0;
  EXPECT_EQ(
      RingKeyDistance(MakeScanContext(Arcs(block, 5.0, 0), occupancy_only),
                      MakeScanContext(Arcs(split, 5.0, 0), occupancy_only)),
      0.0);
}

}  // namespace
}  // namespace slam
