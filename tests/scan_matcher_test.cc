// Scan matching (point-to-line ICP, correlative search) and the odometry
// noise model on synthetic scans with known poses.
#include "frontends/laser/scan_matcher.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "frontends/laser/odometry_model.h"
#include "frontends/laser/scan_simulator.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

// A 12 x 8 m room with a few pillars and an inner wall, so that every pose
// sees structure in both directions.
std::vector<Wall> Room() {
  std::vector<Wall> walls = RectangleWalls(-6, -4, 6, 4);
  for (const Wall& w : RectangleWalls(1.0, 1.0, 1.6, 1.4)) walls.push_back(w);
  for (const Wall& w : RectangleWalls(-3.0, -2.5, -2.4, -1.5))
    walls.push_back(w);
  walls.push_back({Eigen::Vector2d(-1, 4), Eigen::Vector2d(-1, 2)});
  walls.push_back({Eigen::Vector2d(3, -4), Eigen::Vector2d(4, -2.5)});
  return walls;
}

Points2 Scan(const std::vector<Wall>& walls, const Pose2& pose, double sigma,
             std::mt19937* rng, double outlier_fraction = 0.0,
             double fov = M_PI) {
  ScanGeometry g;
  g.num_beams = 181;
  g.angle_min = -fov / 2;
  g.angle_increment = fov / 180;
  g.max_range = 20.0;
  std::vector<float> ranges = SimulateScan(walls, pose, g, sigma, rng);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (float& r : ranges) {
    if (u(*rng) < outlier_fraction) r = static_cast<float>(0.3 + 5.0 * u(*rng));
  }
  return RangesToPoints(ranges, g.angle_min, g.angle_increment, 0.05,
                        g.max_range);
}

double AngleError(double a, double b) {
  return std::abs(NormalizeAngle(a - b));
}

struct Fixture {
  Pose2 a{0.5, -0.3, 0.2};
  Pose2 b{1.1, 0.1, 0.45};
  MatchTarget target;
  Points2 source;
  Pose2 truth;  // b in a's frame.
};

Fixture MakeFixture(double outliers, double fov, unsigned seed) {
  std::mt19937 rng(seed);
  Fixture f;
  const std::vector<Wall> walls = Room();
  f.target.Build(VoxelFilter(Scan(walls, f.a, 0.01, &rng, 0.0, fov), 0.03), 0.3,
                 0.15);
  f.source = Scan(walls, f.b, 0.01, &rng, outliers, fov);
  f.truth = f.a.Inverse() * f.b;
  return f;
}

TEST(ScanMatcherTest, IcpRecoversKnownTransformWithNoiseAndOutliers) {
  // 270 degree scans: the two views overlap partly; 10% of the beams of the
  // source are random short readings (outliers).
  Fixture f = MakeFixture(0.1, 1.5 * M_PI, 1);
  const Pose2 guess = f.truth * Pose2(0.08, -0.06, 0.04);
  const MatchResult r = f.target.Icp(f.source, guess, IcpOptions());
  ASSERT_TRUE(r.success);
  EXPECT_LT((r.pose.t - f.truth.t).norm(), 0.01);
  EXPECT_LT(AngleError(r.pose.theta, f.truth.theta), 0.003);
  EXPECT_GT(r.fitness, 0.6);
  EXPECT_LT(r.fitness, 0.95);  // The outliers are not inliers.
  // The guess itself was far worse.
  EXPECT_GT((guess.t - f.truth.t).norm(), 0.09);
}

TEST(ScanMatcherTest, CorrelativeSearchThenIcpFromAFarGuess) {
  Fixture f = MakeFixture(0.05, M_PI, 2);
  // Too far for ICP alone within the 0.3 m correspondence gate.
  const Pose2 guess = f.truth * Pose2(0.45, -0.35, 0.25);
  CorrelativeOptions c;
  c.window_xy = 0.8;
  c.window_theta = 0.4;
  c.step_theta = 0.01;
  const MatchResult r = f.target.Match(f.source, guess, c, IcpOptions());
  ASSERT_TRUE(r.success);
  EXPECT_LT((r.pose.t - f.truth.t).norm(), 0.01);
  EXPECT_LT(AngleError(r.pose.theta, f.truth.theta), 0.003);
  EXPECT_GT(r.score, 0.5);
}

TEST(ScanMatcherTest, CorrelativeBranchAndBoundEqualsExhaustiveSearch) {
  Fixture f = MakeFixture(0.0, M_PI, 3);
  const Pose2 guess = f.truth * Pose2(0.2, 0.1, -0.05);
  CorrelativeOptions c;
  c.window_xy = 0.4;
  c.window_theta = 0.1;
  c.step_theta = 0.02;
  double score = 0.0;
  const Pose2 bb = f.target.Correlative(f.source, guess, c, &score);
  c.levels = 0;  // Every lattice point evaluated at the fine level.
  double exhaustive_score = 0.0;
  const Pose2 ex = f.target.Correlative(f.source, guess, c, &exhaustive_score);
  EXPECT_NEAR(score, exhaustive_score, 1e-9);
  EXPECT_LT((bb.t - ex.t).norm(), 1e-9);
  EXPECT_NEAR(bb.theta, ex.theta, 1e-12);
}

// The same where the source reaches beyond the target's lower-left edge
// (partial overlap, as a loop query sticking out of a place's submap): a
// wall 2 m long and the same wall seen 1.5 m to the left, searched over
// +-2 m with six levels. The bound of a block of offsets must count the
// points that land on the grid only for the block's larger offsets; it
// dropped them and pruned the match (score 0 against 0.88).
TEST(ScanMatcherTest,
     CorrelativeBranchAndBoundEqualsExhaustiveSearchAtTheEdge) {
  Points2 wall, seen;
  for (int i = 0; i <= 100; ++i) wall.emplace_back(0.02 * i, 0.0);
  for (int i = 0; i <= 20; ++i) seen.emplace_back(-1.5 + 0.1 * i, 0.0);
  MatchTarget target;
  target.Build(wall, 0.3, 0.15);
  CorrelativeOptions c;
  c.window_xy = 2.0;
  c.window_theta = 0.0;
  c.levels = 6;
  double score = 0.0;
  const Pose2 bb = target.Correlative(seen, Pose2(), c, &score);
  c.levels = 0;
  double exhaustive_score = 0.0;
  target.Correlative(seen, Pose2(), c, &exhaustive_score);
  EXPECT_GT(exhaustive_score, 0.8);
  EXPECT_NEAR(score, exhaustive_score, 1e-9);
  EXPECT_NEAR(bb.t.x(), 1.5, 0.06);
}

// A target rebuilt for new points (the tracking's submap is rebuilt at
// every keyframe) forgets the grids of the old ones: searched after a
// larger scene around the same guess with the same levels (grids that would
// cover the new search), it gives what a fresh target gives, to the last
// bit.
TEST(ScanMatcherTest, CorrelativeOnARebuiltTargetEqualsAFreshOne) {
  Fixture f = MakeFixture(0.0, M_PI, 4);
  const Pose2 guess = f.truth * Pose2(0.15, -0.1, 0.04);
  CorrelativeOptions c;
  c.window_xy = 0.5;
  c.window_theta = 0.1;
  c.step_theta = 0.02;
  c.levels = 4;
  double fresh_score = 0.0;
  const Pose2 fresh = f.target.Correlative(f.source, guess, c, &fresh_score);
  EXPECT_GT(fresh_score, 0.5);

  MatchTarget reused;
  Points2 big;  // A 20 m x 20 m scene of scattered walls: larger grids.
  for (int i = 0; i <= 400; ++i) {
    big.emplace_back(-10.0 + 0.05 * i, -10.0);
    big.emplace_back(-10.0 + 0.05 * i, 10.0);
    big.emplace_back(-10.0, -10.0 + 0.05 * i);
  }
  reused.Build(big, 0.3, 0.15);
  CorrelativeOptions wide = c;
  wide.window_xy = 3.0;
  double big_score = 0.0;
  reused.Correlative(f.source, guess, wide, &big_score);
  reused.Build(f.target.points(), 0.3, 0.15);
  double score = 0.0;
  const Pose2 again = reused.Correlative(f.source, guess, c, &score);
  EXPECT_EQ(score, fresh_score);
  EXPECT_EQ(again.t.x(), fresh.t.x());
  EXPECT_EQ(again.t.y(), fresh.t.y());
  EXPECT_EQ(again.theta, fresh.theta);
}

// A minimum score only prunes: below the best score the answer is the
// same; above it, the search reports nothing (initial pose, score 0).
// A correlative search case: a guess 0.36 m and 0.1 rad from the truth, a
// window covering it, and the exact search's best pose and score.
struct CorrelativeCase {
  Fixture f;
  Pose2 guess;
  CorrelativeOptions c;
  Pose2 best;
  double score = 0.0;
};

CorrelativeCase MakeCorrelativeCase() {
  CorrelativeCase t;
  t.f = MakeFixture(0.0, M_PI, 5);
  t.guess = t.f.truth * Pose2(0.3, -0.2, 0.1);
  t.c.window_xy = 0.6;
  t.c.window_theta = 0.2;
  t.c.step_theta = 0.01;
  t.best = t.f.target.Correlative(t.f.source, t.guess, t.c, &t.score);
  return t;
}

TEST(ScanMatcherTest, CorrelativeMinimumScorePrunesWithoutChangingTheBest) {
  CorrelativeCase t = MakeCorrelativeCase();
  const Fixture& f = t.f;
  const Pose2& guess = t.guess;
  CorrelativeOptions& c = t.c;
  const Pose2& best = t.best;
  const double score = t.score;
  ASSERT_GT(score, 0.3);
  c.min_score = score - 0.1;
  double pruned_score = 0.0;
  const Pose2 pruned = f.target.Correlative(f.source, guess, c, &pruned_score);
  EXPECT_NEAR(pruned_score, score, 1e-12);
  EXPECT_LT((pruned.t - best.t).norm(), 1e-12);
  EXPECT_NEAR(pruned.theta, best.theta, 1e-12);
  c.min_score = score + 0.01;
  const Pose2 none = f.target.Correlative(f.source, guess, c, &pruned_score);
  EXPECT_EQ(pruned_score, 0.0);
  EXPECT_LT((none.t - guess.t).norm(), 1e-12);
  EXPECT_NEAR(none.theta, guess.theta, 1e-12);
}

// The work bound of the correlative search: a bound above what the search
// needs leaves it exact; a bound the root level alone exceeds stops it
// before any pose is scored (the initial pose, score 0); a bound in
// between still returns a pose near the truth, from the branches it
// explored first (the most promising).
TEST(ScanMatcherTest, CorrelativeWorkBoundStopsTheSearch) {
  CorrelativeCase t = MakeCorrelativeCase();
  ASSERT_GT(t.score, 0.3);
  const Points2& source = t.f.source;
  double score = 0.0;
  t.c.max_evaluations = 1e12;
  const Pose2 bounded = t.f.target.Correlative(source, t.guess, t.c, &score);
  EXPECT_NEAR(score, t.score, 1e-12);
  EXPECT_LT((bounded.t - t.best.t).norm(), 1e-12);
  t.c.max_evaluations = 1.0;
  const Pose2 stopped = t.f.target.Correlative(source, t.guess, t.c, &score);
  EXPECT_EQ(score, 0.0);
  EXPECT_LT((stopped.t - t.guess.t).norm(), 1e-12);
  // The roots (41 angles, 4 x 4 blocks of 8 x 8 offsets) and about a
  // hundred descents.
  t.c.max_evaluations = (41.0 * 16 + 100) * source.size();
  const Pose2 early = t.f.target.Correlative(source, t.guess, t.c, &score);
  EXPECT_GT(score, 0.5 * t.score);
  EXPECT_LT((early.t - t.f.truth.t).norm(), 0.1);
}

// A target seen from (0.5, -0.3, 0.2) all round (a place's submap).
MatchTarget PlaceTarget(const std::vector<Wall>& walls, std::mt19937* rng) {
  MatchTarget target;
  target.Build(VoxelFilter(Scan(walls, Pose2(0.5, -0.3, 0.2), 0.01, rng, 0.0,
                                2 * M_PI - 0.1),
                           0.03),
               0.3, 0.15);
  return target;
}

// The search of a global loop candidate: 3 m, 0.21 rad, six levels.
CorrelativeOptions GlobalSearch(CorrelativeOptions c, double min_score) {
  c.window_xy = 3.0;
  c.window_theta = 0.21;
  c.levels = 6;
  c.min_score = min_score;
  return c;
}

// A candidate place: its target, the search's guess, and whether it is the
// place the source was seen at.
struct Place {
  const MatchTarget* target;
  Pose2 guess;
  bool right;
};

// The probe of the correlative search (CorrelativeOptions::
// probe_evaluations), as loop closure uses it for global candidates: a
// scan of the room searched as a global candidate (3 m, 0.21 rad, six
// levels, minimum score 0.3) at the right place and at a wrong one (a room
// of the same size cluttered with boxes).
// - Wrong place: no pose reaches the minimum score, and the exact search
//   spends 4e5 look-ups proving it (its bounds are loose: most points lie
//   near some box); with the probe it stops just past the probe (5e4)
//   with the same answer, nothing.
// - Right place (guesses 1.1 m / 0.03 rad and 0.36 m / 0.1 rad off): a
//   pose reaching the score is found within the probe (the peak dominates
//   the bounds), so the search goes on and its answer is the exact
//   search's. (Not always: the depth-first order can reach the peak late,
//   e.g. 4e5 look-ups from 1.5 m off; the probe is set from where true
//   revisits are found, laser_slam.h.)
TEST(ScanMatcherTest, CorrelativeProbeStopsAtAWrongPlaceAndKeepsTheRightOne) {
  CorrelativeCase t = MakeCorrelativeCase();
  std::vector<Wall> clutter = RectangleWalls(-6, -4, 6, 4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 25; ++i) {
    const double x = -5.5 + 10.5 * u(rng);
    const double y = -3.5 + 6.5 * u(rng);
    const double w = 0.2 + 0.4 * u(rng);
    const double h = 0.2 + 0.4 * u(rng);
    for (const Wall& wall : RectangleWalls(x, y, x + w, y + h)) {
      clutter.push_back(wall);
    }
  }
  const MatchTarget wrong = PlaceTarget(clutter, &rng);
  const CorrelativeOptions exact = GlobalSearch(t.c, 0.3);
  CorrelativeOptions probed = exact;
  probed.probe_evaluations = 5e4;
  const Points2 source = VoxelFilter(t.f.source, 0.2);
  for (const Place& place :
       {Place{&t.f.target, t.f.truth * Pose2(1.0, -0.5, 0.03), true},
        Place{&t.f.target, t.guess, true},
        Place{&wrong, Pose2(0.5, 0.2, 0.1), false}}) {
    double exact_score = 0.0, score = 0.0;
    CorrelativeWork exact_work, work;
    const Pose2 best = place.target->Correlative(source, place.guess, exact,
                                                 &exact_score, &exact_work);
    const Pose2 pose =
        place.target->Correlative(source, place.guess, probed, &score, &work);
    EXPECT_FALSE(exact_work.probe_stopped);
    EXPECT_EQ(work.probe_stopped, !place.right);
    EXPECT_EQ(score, exact_score);
    EXPECT_LT((pose.t - best.t).norm(), 1e-12);
    EXPECT_NEAR(pose.theta, best.theta, 1e-12);
    if (place.right) {
      EXPECT_GT(score, 0.4);
      EXPECT_LT((pose.t - t.f.truth.t).norm(), 0.1);
      EXPECT_EQ(work.evaluations, exact_work.evaluations);
    } else {
      EXPECT_EQ(exact_score, 0.0);
      EXPECT_GT(exact_work.evaluations, 5 * probed.probe_evaluations);
      // Past the probe by at most one expansion (4 children).
      EXPECT_LT(work.evaluations,
                probed.probe_evaluations + 4.0 * source.size());
    }
  }
}

// The verified search (MatchTarget::Verifier), as loop closure uses it
// (loop_search_verifications = 1): each pose the search finds reaching the
// minimum score is matched by ICP at once; a failing match stops the search
// (the place is wrong), a passing one lets it go on to its best pose. Here
// a scan of the room is searched as a global candidate (3 m, 0.21 rad, six
// levels) at a wrong place that reaches the score (a room of the same size
// with other inner walls: the outer walls fit, the rest does not) and at
// the right place.
// - Wrong place: the search without verification runs to its best pose,
//   which fails ICP; the verified search stops at the first pose, in a
//   small fraction of the look-ups, and reports nothing.
// - Right place: the first pose passes, and the answer and the work are
//   those of the search without verification.
TEST(ScanMatcherTest, CorrelativeVerifiedSearchStopsAtAWrongPlaceThatScores) {
  CorrelativeCase t = MakeCorrelativeCase();
  std::vector<Wall> other = RectangleWalls(-6, -4, 6, 4);
  for (const Wall& w : RectangleWalls(-1.0, 0.5, 0.0, 2.5)) other.push_back(w);
  for (const Wall& w : RectangleWalls(2.0, -2.0, 3.5, -1.2)) {
    other.push_back(w);
  }
  other.push_back({Eigen::Vector2d(-4, -4), Eigen::Vector2d(-4, -1.5)});
  std::mt19937 rng(11);
  const MatchTarget wrong = PlaceTarget(other, &rng);
  const CorrelativeOptions c = GlobalSearch(t.c, 0.2);
  const Points2 source = VoxelFilter(t.f.source, 0.2);
  const Points2& query = t.f.source;
  for (const Place& place :
       {Place{&t.f.target, t.f.truth * Pose2(1.0, -0.5, 0.03), true},
        Place{&wrong, Pose2(0.5, 0.2, 0.1), false}}) {
    const MatchTarget& target = *place.target;
    auto passes = [&](const Pose2& pose) {
      const MatchResult m = target.Icp(query, pose, IcpOptions());
      return m.success && m.fitness >= 0.8;
    };
    // As laser_slam's: no more ICP once a pose has passed.
    int calls = 0;
    bool passed = false;
    const MatchTarget::Verifier verify = [&](const Pose2& pose, double) {
      if (passed) return true;
      ++calls;
      passed = passes(pose);
      return passed;
    };
    double plain_score = 0.0, score = 0.0;
    CorrelativeWork plain_work, work;
    const Pose2 best =
        target.Correlative(source, place.guess, c, &plain_score, &plain_work);
    const Pose2 pose =
        target.Correlative(source, place.guess, c, &score, &work, &verify);
    EXPECT_GT(plain_score, c.min_score);
    EXPECT_EQ(calls, 1);
    if (place.right) {
      EXPECT_TRUE(passes(best));
      EXPECT_FALSE(work.verify_stopped);
      EXPECT_EQ(score, plain_score);
      EXPECT_LT((pose.t - best.t).norm(), 1e-12);
      EXPECT_NEAR(pose.theta, best.theta, 1e-12);
      EXPECT_LT((pose.t - t.f.truth.t).norm(), 0.1);
      EXPECT_EQ(work.evaluations, plain_work.evaluations);
    } else {
      EXPECT_FALSE(passes(best));
      EXPECT_EQ(work.verified, 1);
      EXPECT_TRUE(work.verify_stopped);
      EXPECT_EQ(score, 0.0);
      EXPECT_LT((pose.t - place.guess.t).norm(), 1e-12);
      EXPECT_EQ(work.evaluations, plain_work.first_found_evaluations);
      // 7.9e4 against 4.5e5 look-ups.
      EXPECT_LT(work.evaluations, 0.25 * plain_work.evaluations);
    }
  }
}

TEST(ScanMatcherTest, IcpFailsWithoutOverlap) {
  std::mt19937 rng(4);
  MatchTarget target;
  target.Build(Points2{}, 0.3, 0.15);
  const MatchResult r = target.Icp(Scan(Room(), Pose2(0, 0, 0), 0.01, &rng),
                                   Pose2(), IcpOptions());
  EXPECT_FALSE(r.success);
}

TEST(ScanMatcherTest, CovarianceIsLargeAlongACorridor) {
  // Two parallel walls along x, ends beyond the laser's range: the match
  // constrains y and theta, not x.
  std::vector<Wall> walls = {
      {Eigen::Vector2d(-100, -1), Eigen::Vector2d(100, -1)},
      {Eigen::Vector2d(-100, 1), Eigen::Vector2d(100, 1)}};
  std::mt19937 rng(5);
  MatchTarget target;
  target.Build(VoxelFilter(Scan(walls, Pose2(0, 0, 0), 0.01, &rng), 0.03), 0.3,
               0.15);
  const Points2 source = Scan(walls, Pose2(0.2, 0.05, 0.02), 0.01, &rng);
  const MatchResult r = target.Icp(source, Pose2(0.2, 0.0, 0.0), IcpOptions());
  ASSERT_TRUE(r.success);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(r.covariance);
  EXPECT_GT(eig.eigenvalues()[0], 0.0);
  EXPECT_GT(r.covariance(0, 0), 100.0 * r.covariance(1, 1));
  // y is recovered.
  EXPECT_NEAR(r.pose.t.y(), 0.05, 0.01);

  // In the room every direction is constrained: a small covariance.
  Fixture f = MakeFixture(0.0, M_PI, 6);
  const MatchResult room = f.target.Icp(f.source, f.truth, IcpOptions());
  ASSERT_TRUE(room.success);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> room_eig(room.covariance);
  EXPECT_GT(room_eig.eigenvalues()[0], 0.0);
  EXPECT_LT(room.covariance(0, 0), 0.01 * r.covariance(0, 0));
  EXPECT_LT(std::sqrt(room.covariance(0, 0)), 0.05);
}

TEST(ScanMatcherTest, PriorHoldsTheCorridorDirectionOnly) {
  // In a corridor along x the points fix y and theta. A prior (here off by
  // 0.15 m in x and 0.1 m in y from the truth) holds x where the points
  // say nothing, but barely moves y, which the points constrain.
  std::vector<Wall> walls = {
      {Eigen::Vector2d(-100, -1), Eigen::Vector2d(100, -1)},
      {Eigen::Vector2d(-100, 1), Eigen::Vector2d(100, 1)}};
  std::mt19937 rng(7);
  MatchTarget target;
  target.Build(VoxelFilter(Scan(walls, Pose2(0, 0, 0), 0.01, &rng), 0.03), 0.3,
               0.15);
  const Pose2 truth(0.2, 0.05, 0.02);
  const Points2 source = Scan(walls, truth, 0.01, &rng);
  IcpPrior prior;
  prior.pose = Pose2(0.35, 0.15, 0.02);
  prior.information = Eigen::Vector3d(10.0, 1.0, 10.0).asDiagonal();
  const Pose2 start(0.6, 0.0, 0.0);
  const MatchResult with = target.Icp(source, start, IcpOptions(), &prior);
  ASSERT_TRUE(with.success);
  EXPECT_NEAR(with.pose.t.x(), prior.pose.t.x(), 0.02);
  EXPECT_NEAR(with.pose.t.y(), truth.t.y(), 0.01);
  EXPECT_NEAR(with.pose.theta, truth.theta, 0.005);
  // Without the prior x wanders off (little pulls it along the corridor).
  const MatchResult without = target.Icp(source, start, IcpOptions());
  ASSERT_TRUE(without.success);
  EXPECT_GT(std::abs(without.pose.t.x() - prior.pose.t.x()),
            3.0 * std::abs(with.pose.t.x() - prior.pose.t.x()));
  // The covariance is that of the points alone, with or without the prior.
  EXPECT_GT(with.covariance(0, 0), 100.0 * with.covariance(1, 1));
}

TEST(OdometryModelTest, CovarianceMatchesSampledMotionModel) {
  OdometryNoise noise;
  noise.min_sigma_xy = 0.0;
  noise.min_sigma_theta = 0.0;
  const Pose2 a(1.0, 2.0, 0.3);
  for (const Pose2& step :
       {Pose2(0.5, 0.1, 0.2), Pose2(-0.4, 0.05, -0.1), Pose2(0.3, -0.2, 0.6)}) {
    const Pose2 b = a * step;
    const OdometryDelta d = OdometryMotion(a, b, noise);
    EXPECT_LT((d.delta.t - step.t).norm(), 1e-12);
    EXPECT_NEAR(d.delta.theta, step.theta, 1e-12);
    // Sample the three-step model with small noise (alphas scaled down, so
    // that first-order propagation holds) and compare covariances.
    OdometryNoise small = noise;
    small.alpha1 *= 0.01;
    small.alpha2 *= 0.01;
    small.alpha3 *= 0.01;
    small.alpha4 *= 0.01;
    const Eigen::Matrix3d model = OdometryMotion(a, b, small).covariance;
    double trans = step.t.norm();
    double rot1 = std::atan2(step.t.y(), step.t.x());
    if (std::abs(rot1) > M_PI / 2) {
      rot1 = NormalizeAngle(rot1 + M_PI);
      trans = -trans;
    }
    const double rot2 = step.theta - rot1;
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0.0, 1.0);
    const int samples = 200000;
    Eigen::Matrix3d sampled = Eigen::Matrix3d::Zero();
    for (int k = 0; k < samples; ++k) {
      const double r1 = rot1 + n(rng) * std::sqrt(small.alpha1 * rot1 * rot1 +
                                                  small.alpha2 * trans * trans);
      const double tr =
          trans +
          n(rng) * std::sqrt(small.alpha3 * trans * trans +
                             small.alpha4 * (rot1 * rot1 + rot2 * rot2));
      const double r2 = rot2 + n(rng) * std::sqrt(small.alpha1 * rot2 * rot2 +
                                                  small.alpha2 * trans * trans);
      const Eigen::Vector3d v(tr * std::cos(r1) - step.t.x(),
                              tr * std::sin(r1) - step.t.y(),
                              NormalizeAngle(r1 + r2 - step.theta));
      sampled += v * v.transpose();
    }
    sampled /= samples;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(model(i, i), sampled(i, i), 0.03 * sampled(i, i) + 1e-12)
          << "component " << i;
    }
  }
}

TEST(OdometryModelTest, GrowsWithMotionAndStaysPositiveDefinite) {
  const OdometryNoise noise;
  const Pose2 a(0, 0, 0);
  const Eigen::Matrix3d still = OdometryMotion(a, a, noise).covariance;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(still);
  EXPECT_GT(eig.eigenvalues()[0], 0.0);
  const Eigen::Matrix3d short_step =
      OdometryMotion(a, Pose2(0.1, 0, 0), noise).covariance;
  const Eigen::Matrix3d long_step =
      OdometryMotion(a, Pose2(1.0, 0, 0), noise).covariance;
  EXPECT_GT(long_step(0, 0), short_step(0, 0));
  EXPECT_GT(long_step(1, 1), short_step(1, 1));
  EXPECT_GT(long_step(2, 2), short_step(2, 2));
  EXPECT_GT(short_step(0, 0), still(0, 0));
  // A turn on the spot: the heading variance grows with the angle.
  const Eigen::Matrix3d turn =
      OdometryMotion(a, Pose2(0, 0, 1.0), noise).covariance;
  EXPECT_GT(turn(2, 2), 10.0 * still(2, 2));
  // Reverse driving is as uncertain as forward driving (the sign of the
  // y-theta correlation flips with the direction of travel).
  const Eigen::Matrix3d back =
      OdometryMotion(a, Pose2(-1.0, 0, 0), noise).covariance;
  EXPECT_LT((back.diagonal() - long_step.diagonal()).norm(), 1e-12);
  EXPECT_NEAR(back(1, 2), -long_step(1, 2), 1e-12);
}

}  // namespace
}  // namespace slam
