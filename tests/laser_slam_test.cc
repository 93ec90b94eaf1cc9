// Laser SLAM end to end: loop-closure verification on synthetic scans, the
// whole pipeline on a synthetic CARMEN log with known poses (through the
// library and through `slam run`), and the real ACES log.
#include "frontends/laser/laser_slam.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>

#include "datasets/carmen_io.h"
#include "datasets/relations_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/laser/laser_map.h"
#include "frontends/laser/scan_simulator.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::DatasetPath;
using testing::RunSlam;
using testing::TempDir;

// A square ring corridor around a block, with niches and pillars along the
// walls so that no stretch is a featureless corridor.
// Random clutter boxes on the outer walls (fixed seed). Off: with 40 of them
// the tracking drifts in heading (a known weakness with small objects,
// see the notes of the laser frontend).
constexpr int kClutter = 0;
std::vector<Wall> RingWorld() {
  std::vector<Wall> walls = RectangleWalls(-10, -7, 10, 7);
  for (const Wall& w : RectangleWalls(-7, -4, 7, 4)) walls.push_back(w);
  const double boxes[][4] = {
      {-5, -6.9, -4.4, -6.3}, {2, -6.9, 2.8, -6.5},   {9.2, -2, 9.9, -1.2},
      {9.4, 3, 9.9, 3.6},     {3, 6.3, 3.5, 6.9},     {-2, 6.5, -1, 6.9},
      {-9.9, 1, -9.3, 1.8},   {-9.9, -3.5, -9.5, -3}, {-1, -4.5, -0.5, -4},
      {7.1, 0.5, 7.6, 1.2},   {0.5, 4, 1.2, 4.5},     {-7.6, -1, -7.1, -0.2}};
  for (const auto& b : boxes) {
    for (const Wall& w : RectangleWalls(b[0], b[1], b[2], b[3])) {
      walls.push_back(w);
    }
  }
  // Irregular clutter on the outer walls (fixed seed): real corridors are
  // rarely periodic, and a periodic one aliases any scan matcher.
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < kClutter; ++i) {
    const double along = u(rng), size = 0.15 + 0.3 * u(rng);
    const double depth = 0.1 + 0.3 * u(rng);
    Eigen::Vector2d c;
    switch (i % 4) {
      case 0:
        c = {-9.5 + 19 * along, -7 + depth / 2};
        break;
      case 1:
        c = {10 - depth / 2, -6.5 + 13 * along};
        break;
      case 2:
        c = {-9.5 + 19 * along, 7 - depth / 2};
        break;
      default:
        c = {-10 + depth / 2, -6.5 + 13 * along};
        break;
    }
    for (const Wall& w : RectangleWalls(c.x() - size / 2, c.y() - size / 2,
                                        c.x() + size / 2, c.y() + size / 2)) {
      walls.push_back(w);
    }
  }
  return walls;
}

// Poses along the closed polygon `corners` (each side a corridor centre
// line), `laps` times round, `step` metres apart; at each corner the robot
// turns in place, in one step or in `turn_steps` steps.
std::vector<Pose2> PolygonPath(const std::vector<Eigen::Vector2d>& corners,
                               double laps, double step, int turn_steps) {
  const int sides = static_cast<int>(corners.size());
  std::vector<double> lengths(sides);
  double perimeter = 0.0;
  for (int i = 0; i < sides; ++i) {
    lengths[i] = (corners[(i + 1) % sides] - corners[i]).norm();
    perimeter += lengths[i];
  }
  std::vector<Pose2> path;
  for (double s = 0; s < laps * perimeter; s += step) {
    double u = std::fmod(s, perimeter);
    int side = 0;
    while (u > lengths[side]) {
      u -= lengths[side];
      side = (side + 1) % sides;
    }
    const Eigen::Vector2d a = corners[side], b = corners[(side + 1) % sides];
    const Eigen::Vector2d dir = (b - a).normalized();
    const Eigen::Vector2d p = a + u * dir;
    const double heading = std::atan2(dir.y(), dir.x());
    if (turn_steps > 1 && !path.empty() &&
        std::abs(NormalizeAngle(heading - path.back().theta)) > 0.1) {
      const double turn = NormalizeAngle(heading - path.back().theta);
      for (int i = 1; i < turn_steps; ++i) {
        path.emplace_back(path.back().t.x(), path.back().t.y(),
                          path.back().theta + turn / turn_steps);
      }
    }
    path.emplace_back(p.x(), p.y(), heading);
  }
  return path;
}

// The centre line of the ring corridor.
std::vector<Pose2> RingPath(double laps, double step, int turn_steps = 1) {
  return PolygonPath({{-8.5, -5.5}, {8.5, -5.5}, {8.5, 5.5}, {-8.5, 5.5}}, laps,
                     step, turn_steps);
}

struct SyntheticLog {
  CarmenLog log;
  std::vector<Pose2> truth;
  std::vector<Pose2> odometry;
};

// Scans from the true poses; odometry with a scale error, a heading bias
// and noise, starting at the true first pose, then the odometry faults.
// Scans first_blind .. first_blind + blind - 1 see nothing (every beam at
// max range: the laser blocked, or open space).
struct LogFaults {
  std::vector<OdometryFault> odometry;
  int first_blind = 0;
  int blind = 0;
  int turn_steps = 1;  // RingPath.
  // The laser's true beam spacing is the logged one times this (a
  // miscalibrated or misreported field of view): every scan is distorted
  // the same way, so the scan matches fit tightly but underestimate every
  // turn by this factor, a bias their covariances do not know.
  double angle_scale = 1.0;
};
SyntheticLog MakeSyntheticLog(const std::vector<Wall>& walls,
                              std::vector<Pose2> truth, unsigned seed,
                              const LogFaults& faults) {
  SyntheticLog out;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  out.truth = std::move(truth);
  ScanGeometry g;  // 181 beams, 1 deg, from -90 deg: the FLASER default.
  g.max_range = 20.0;
  ScanGeometry seen = g;  // The beams' true directions.
  seen.angle_min *= faults.angle_scale;
  seen.angle_increment *= faults.angle_scale;
  Pose2 odom = out.truth[0];
  for (size_t i = 0; i < out.truth.size(); ++i) {
    if (i > 0) {
      const Pose2 d = out.truth[i - 1].Inverse() * out.truth[i];
      const double len = d.t.norm();
      const Pose2 noisy(d.t.x() * 1.03 + 0.005 * n(rng),
                        d.t.y() + 0.005 * n(rng),
                        d.theta * 1.02 + 0.004 * len + 0.002 * n(rng));
      odom = odom * noisy;
    }
    out.odometry.push_back(odom);
  }
  for (const OdometryFault& fault : faults.odometry) {
    out.odometry = ApplyOdometryFault(out.odometry, fault);
  }
  for (size_t i = 0; i < out.truth.size(); ++i) {
    LaserScan scan;
    scan.stamp = SecondsToNs(10.0 + 0.2 * i);
    scan.odom = out.odometry[i];
    scan.logged_pose = out.odometry[i];
    scan.angle_min = g.angle_min;
    scan.angle_increment = g.angle_increment;
    scan.max_range = g.max_range;
    const int index = static_cast<int>(i);
    scan.ranges =
        index >= faults.first_blind && index < faults.first_blind + faults.blind
            ? std::vector<float>(g.num_beams, static_cast<float>(g.max_range))
            : SimulateScan(walls, out.truth[i], seen, 0.01, &rng);
    scan.tag = "FLASER";
    out.log.scans.push_back(scan);
    out.log.odometry.push_back({scan.stamp, scan.odom, 0.5, 0.0});
  }
  out.log.params["robot_front_laser_max"] = "20";
  return out;
}

// The ring corridor, `laps` times round in 0.1 m steps.
SyntheticLog MakeSyntheticLog(double laps, unsigned seed,
                              const LogFaults& faults = LogFaults()) {
  return MakeSyntheticLog(RingWorld(), RingPath(laps, 0.1, faults.turn_steps),
                          seed, faults);
}

double PositionRmse(const Trajectory& est, const std::vector<Pose2>& truth) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    sum += (est[i].pose.t.head<2>() - truth[i].t).squaredNorm();
  }
  return std::sqrt(sum / truth.size());
}

double PositionRmse(const std::vector<Pose2>& est,
                    const std::vector<Pose2>& truth) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    sum += (est[i].t - truth[i].t).squaredNorm();
  }
  return std::sqrt(sum / truth.size());
}

// Laser SLAM over a whole log: the scans' trajectory, the statistics into
// *stats.
Trajectory RunLaserSlam(const LaserSlamConfig& config, const CarmenLog& log,
                        LaserSlamStats* stats) {
  LaserSlam slam(config);
  for (const LaserScan& scan : log.scans) slam.AddScan(scan);
  slam.Finish();
  *stats = slam.stats();
  return slam.ScanTrajectory();
}

Points2 ScanPoints(const std::vector<Wall>& walls, const Pose2& pose,
                   std::mt19937* rng) {
  ScanGeometry g;
  g.max_range = 20.0;
  return RangesToPoints(SimulateScan(walls, pose, g, 0.01, rng), g.angle_min,
                        g.angle_increment, 0.1, g.max_range);
}

TEST(LaserSlamTest, LoopVerificationAcceptsTrueAndRejectsWrongClosure) {
  std::mt19937 rng(11);
  const std::vector<Wall> walls = RingWorld();
  const LaserSlamConfig config;
  // Target: three views near (-5, -5.5) in the frame of the middle one.
  const Pose2 anchor(-5.0, -5.5, 0.0);
  Points2 target_points;
  for (double dx : {-0.6, 0.0, 0.6}) {
    const Pose2 view(anchor.t.x() + dx, anchor.t.y(), 0.0);
    const Points2 p =
        TransformPoints(anchor.Inverse() * view, ScanPoints(walls, view, &rng));
    target_points.insert(target_points.end(), p.begin(), p.end());
  }
  MatchTarget target;
  target.Build(VoxelFilter(target_points, config.submap_voxel), 0.3, 0.15);
  CorrelativeOptions search = config.loop_correlative;
  search.window_xy = 2.0;

  // The same place seen again, with a 1.2 m, 0.15 rad wrong guess.
  const Pose2 revisit(-4.7, -5.3, 0.1);
  const Pose2 truth = anchor.Inverse() * revisit;
  const Points2 query = ScanPoints(walls, revisit, &rng);
  const Pose2 guess = truth * Pose2(0.9, -0.8, 0.15);
  const MatchResult good = target.Match(query, guess, search, config.icp);
  EXPECT_TRUE(LoopMatchPasses(good, config))
      << "score " << good.score << " inliers " << good.num_inliers << " of "
      << good.num_correspondences;
  EXPECT_LT((good.pose.t - truth.t).norm(), 0.03);
  EXPECT_LT(std::abs(NormalizeAngle(good.pose.theta - truth.theta)), 0.01);

  // A place with a different layout (a corner of the ring, facing the
  // wall): no consistent alignment within the window. (Two stretches of
  // plain corridor would align; the consistency check over consecutive
  // keyframes in LaserSlam deals with such aliasing.)
  const Pose2 elsewhere(8.5, 5.5, 0.3);
  const MatchResult bad = target.Match(ScanPoints(walls, elsewhere, &rng),
                                       guess, search, config.icp);
  EXPECT_FALSE(LoopMatchPasses(bad, config))
      << "score " << bad.score << " inliers " << bad.num_inliers << " of "
      << bad.num_correspondences;
}

TEST(LaserSlamTest, SyntheticRingIsMappedWithLoopClosures) {
  const SyntheticLog data = MakeSyntheticLog(1.4, 21);
  LaserSlam slam{LaserSlamConfig()};
  for (const LaserScan& scan : data.log.scans) slam.AddScan(scan);
  slam.Finish();
  const Trajectory est = slam.ScanTrajectory();
  ASSERT_EQ(est.size(), data.truth.size());
  for (size_t i = 0; i < est.size(); ++i) {
    ASSERT_EQ(est[i].stamp, data.log.scans[i].stamp);
  }
  const double odometry_rmse = PositionRmse(data.odometry, data.truth);
  const double slam_rmse = PositionRmse(est, data.truth);
  const LaserSlamStats& s = slam.stats();
  EXPECT_GT(odometry_rmse, 1.0);  // The drift is real...
  EXPECT_LT(slam_rmse, 0.05)      // ... and removed.
      << "odometry " << odometry_rmse << " m";
  EXPECT_GT(s.closures_accepted, 0);
  // Some consistent closures still end down-weighted after the final
  // optimization (see LaserSlam::Finish); most must survive.
  EXPECT_LT(s.closures_rejected, s.closures_accepted);
  EXPECT_EQ(s.tracking_failures, 0);
  EXPECT_GT(s.keyframes, 100);
}

// Wrong odometry (MIT CSAIL's wheel-encoder dropout): a freeze of 8 scans
// while the robot drives on (0.8 m), then the catch-up in one increment,
// and elsewhere a plain jump of 0.4 m, 0.7 rad in one increment. Tracking must
// follow the scans, not the odometry, and the keyframe odometry factors across
// the faults must not pull the graph.
TEST(LaserSlamTest, TrackingSurvivesOdometryFreezeAndJump) {
  // RingPath: 0.1 m steps, turning in place in 6 steps of 15 deg at the
  // corners; the first corner at scans 170-175, the second at 281-286.
  LogFaults faults;
  faults.turn_steps = 6;
  OdometryFault freeze;
  freeze.kind = OdometryFault::kFreeze;
  freeze.first = 171;
  freeze.length = 5;
  OdometryFault jump;
  jump.kind = OdometryFault::kJump;
  jump.first = 330;
  jump.jump = Pose2(0.4, -0.2, 0.7);
  faults.odometry = {freeze, jump};
  const SyntheticLog data = MakeSyntheticLog(1.4, 21, faults);
  LaserSlamConfig config;
  config.loop_closure = false;  // Tracking alone must get it right.
  LaserSlam slam(config);
  for (const LaserScan& scan : data.log.scans) slam.AddScan(scan);
  slam.Finish();
  const Trajectory est = slam.ScanTrajectory();
  ASSERT_EQ(est.size(), data.truth.size());
  // Heading error at the end of the run (no loop closure to repair it).
  const Eigen::Quaterniond& q = est.back().pose.q;
  const double heading_error = std::abs(
      NormalizeAngle(2.0 * std::atan2(q.z(), q.w()) - data.truth.back().theta));
  const LaserSlamStats& s = slam.stats();
  EXPECT_LT(heading_error, 0.05);
  EXPECT_LT(PositionRmse(est, data.truth), 0.2);
  EXPECT_GT(s.odometry_rejected, 0);
  EXPECT_GT(s.odometry_factors_dropped + s.odometry_factors_weakened, 0);
  EXPECT_LE(s.odometry_rejected, 12);  // Only around the two faults.
}

// A fast turn in place whose scan matches best as a slide: in the middle of
// the first corner's turn (3 steps of 30 deg) one scan looks as if taken
// 0.35 m sideways and not turned, with 40 % of its beams on clutter, so
// its best match fits poorly and lies far from the odometry's (right)
// increment. ACES played three times met this at a 22 deg turn: the
// correlative search seeded by the odometry slid 0.75 m instead of
// turning, at a fitness just above the floor, the next scans followed the
// wrong velocity and the pass was mapped 81 deg off. Such a match is now
// rejected and the odometry's prediction kept; with the check off (an
// infinite odometry_break_chi2) the slide is tracked.
TEST(LaserSlamTest, PoorMatchSlidingOffAPlausibleTurnIsRejected) {
  for (unsigned seed : {5u, 6u, 11u}) {
    SCOPED_TRACE(seed);
    LogFaults faults;
    faults.turn_steps = 3;
    SyntheticLog data = MakeSyntheticLog(0.6, seed, faults);
    // The middle step of the first turn in place.
    size_t glitch = 0;
    for (size_t i = 2; i + 1 < data.truth.size() && glitch == 0; ++i) {
      const bool turning =
          (data.truth[i].t - data.truth[i - 1].t).norm() < 1e-9 &&
          (data.truth[i - 1].t - data.truth[i - 2].t).norm() < 1e-9;
      if (turning) glitch = i;
    }
    ASSERT_GT(glitch, 0u);
    const Pose2 slid = data.truth[glitch - 1] * Pose2(0.0, 0.35, 0.0);
    std::mt19937 rng(seed + 100);
    ScanGeometry g;
    g.max_range = 20.0;
    std::vector<float> ranges = SimulateScan(RingWorld(), slid, g, 0.01, &rng);
    std::uniform_real_distribution<double> clutter(0.5, 2.5);
    for (size_t b = 0; b < ranges.size(); b += 5) {  // 2 beams in 5.
      ranges[b] = static_cast<float>(clutter(rng));
      if (b + 1 < ranges.size()) {
        ranges[b + 1] = static_cast<float>(clutter(rng));
      }
    }
    data.log.scans[glitch].ranges = ranges;

    auto run = [&](double break_chi2, LaserSlamStats* stats) {
      LaserSlamConfig config;
      config.loop_closure = false;  // Tracking alone.
      config.odometry_break_chi2 = break_chi2;
      const Trajectory est = RunLaserSlam(config, data.log, stats);
      EXPECT_EQ(est.size(), data.truth.size());
      return (est[glitch].pose.t.head<2>() - data.truth[glitch].t).norm();
    };
    LaserSlamStats off_stats, on_stats;
    const double off = run(std::numeric_limits<double>::infinity(), &off_stats);
    const double on = run(LaserSlamConfig().odometry_break_chi2, &on_stats);
    // Measured: 0.15-0.31 m off, 0.001-0.008 m on.
    EXPECT_GT(off, 0.1) << "the case no longer reproduces the slide";
    EXPECT_EQ(off_stats.tracking_slides_rejected, 0);
    EXPECT_LT(on, 0.05);
    EXPECT_GE(on_stats.tracking_slides_rejected, 1);
    EXPECT_LE(on_stats.tracking_slides_rejected, 2);  // Only at the glitch.
  }
}

// Drift beyond the local loop search: the laser sees nothing for 6 m while
// the odometry jumps by 0.45 rad, so the map after that stretch starts
// rotated and the robot comes back to its start about 8 m from where the
// map puts it, beyond the local search radius. Only the global search
// (Scan Context candidates, verified and checked for consistency) can close
// the loop; the answer is then recovered.
TEST(LaserSlamTest, GlobalLoopSearchClosesLoopBeyondTheLocalRadius) {
  LogFaults faults;
  faults.first_blind = 200;  // On the second side, after the first corner.
  faults.blind = 60;
  OdometryFault jump;
  jump.kind = OdometryFault::kJump;
  jump.first = 230;
  jump.jump = Pose2(0.3, 0.2, 0.45);
  faults.odometry = {jump};
  const SyntheticLog data = MakeSyntheticLog(1.6, 41, faults);
  for (const bool global : {false, true}) {
    LaserSlamConfig config;
    config.loop_global = global;
    LaserSlamStats s;
    const Trajectory est = RunLaserSlam(config, data.log, &s);
    ASSERT_EQ(est.size(), data.truth.size());
    const double rmse = PositionRmse(est, data.truth);
    std::printf(
        "global %d: rmse %.3f m, closures %d accepted (%d global of %d "
        "proposed), %d rejected, largest correction %.2f m %.1f deg\n",
        global, rmse, s.closures_accepted, s.global_closures_accepted,
        s.global_closures_proposed, s.closures_rejected, s.largest_correction_m,
        s.largest_correction_deg);
    if (global) {
      EXPECT_GT(s.global_closures_accepted, 0);
      EXPECT_GT(s.largest_correction_m, 4.0);
      EXPECT_LT(rmse, 0.1);
    } else {
      EXPECT_GT(rmse, 1.0);  // The drift is real and the local search fails.
    }
  }
}

// A building of four long corridors (3 m wide) round a 44 m x 24 m block,
// with boxes on both walls at irregular places (fixed seed per corridor),
// its corner at kBuilding: far from the origin of the odometry frame, as in
// real logs, so that corrections are not all rotations about a nearby
// point.
const Eigen::Vector2d kBuilding(120.0, 80.0);
// With `aliased`, the north corridor is the south one turned by 180 deg
// about the centre: walked westwards it looks exactly like the south one
// walked eastwards.
std::vector<Wall> BuildingWorld(bool aliased) {
  std::vector<Wall> walls = RectangleWalls(0, 0, 50, 30);
  for (const Wall& w : RectangleWalls(3, 3, 47, 27)) walls.push_back(w);
  // Corridor side s in its own frame: `a` along it, `c` across (0 at the
  // outer wall, 3 at the block), mapped into the world.
  auto to_world = [](int side, double a, double c) -> Eigen::Vector2d {
    switch (side) {
      case 0:
        return {a, c};  // South, eastwards.
      case 1:
        return {50 - c, a};  // East, northwards.
      case 2:
        return {50 - a, 30 - c};  // North, westwards.
      default:
        return {c, 30 - a};  // West, southwards.
    }
  };
  for (int side = 0; side < 4; ++side) {
    std::mt19937 rng(aliased && side == 2 ? 100 : 100 + side);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double length = side % 2 == 0 ? 46.0 : 26.0;
    for (double a = 4.0 + 2.0 * u(rng); a < length - 1.0;
         a += 1.5 + 3.0 * u(rng)) {
      const double width = 0.3 + 0.6 * u(rng), depth = 0.2 + 0.4 * u(rng);
      const bool outer = u(rng) < 0.5;
      const Eigen::Vector2d p = to_world(side, a, outer ? 0.0 : 3.0 - depth);
      const Eigen::Vector2d q = to_world(side, a + width, outer ? depth : 3.0);
      for (const Wall& w :
           RectangleWalls(std::min(p.x(), q.x()), std::min(p.y(), q.y()),
                          std::max(p.x(), q.x()), std::max(p.y(), q.y()))) {
        walls.push_back(w);
      }
    }
  }
  for (Wall& w : walls) {
    w.a += kBuilding;
    w.b += kBuilding;
  }
  return walls;
}

std::vector<Pose2> BuildingPath(double laps) {
  const Eigen::Vector2d o = kBuilding;
  return PolygonPath(
      {o + Eigen::Vector2d(1.5, 1.5), o + Eigen::Vector2d(48.5, 1.5),
       o + Eigen::Vector2d(48.5, 28.5), o + Eigen::Vector2d(1.5, 28.5)},
      laps, 0.2, 3);
}

// The default configuration on a building log: the position RMSE of every
// scan against the truth (printed with the loop-closure statistics).
double RunBuilding(const SyntheticLog& data, LaserSlamStats* stats) {
  LaserSlam slam{LaserSlamConfig()};
  for (const LaserScan& scan : data.log.scans) slam.AddScan(scan);
  slam.Finish();
  const Trajectory est = slam.ScanTrajectory();
  EXPECT_EQ(est.size(), data.truth.size());
  if (est.size() != data.truth.size()) return 1e300;
  const LaserSlamStats& s = slam.stats();
  *stats = s;
  const double rmse = PositionRmse(est, data.truth);
  std::printf(
      "rmse %.3f m (odometry %.1f m), closures %d of %d accepted (%d global "
      "of %d proposed, %d stopped by the probe), %d reverted, %d rejected, "
      "largest correction %.2f m %.1f deg, %d of %d searches stopped by a "
      "failed verification, loop search %.2f s of %.2f s\n",
      rmse, PositionRmse(data.odometry, data.truth), s.closures_accepted,
      s.closures_proposed, s.global_closures_accepted,
      s.global_closures_proposed, s.global_searches_probe_stopped,
      s.closures_reverted, s.closures_rejected, s.largest_correction_m,
      s.largest_correction_deg, s.loop_searches_verify_stopped, s.loop_searches,
      s.loop_seconds,
      s.matching_seconds + s.loop_seconds + s.optimization_seconds +
          s.refine_seconds);
  return rmse;
}

// Issue 24's mechanism: a revisit after a long excursion, with the drift
// beyond the local loop search. Round the building once (148 m) and 25 m
// on, the laser blind for 6 m halfway (open space) while the odometry turns
// by a wrong 0.6 rad: the map of the second half is rotated by 34 deg about
// the far corner, and the start is revisited about 25 m from where the map
// puts it. The default configuration must recognise the place, accept the
// large correction and bend the graph without tearing it.
TEST(LaserSlamTest, RevisitAfterLongExcursionIsClosed) {
  LogFaults faults;
  faults.turn_steps = 3;
  faults.first_blind = 400;  // North corridor, 6 m past its start.
  faults.blind = 30;
  OdometryFault jump;
  jump.kind = OdometryFault::kJump;
  jump.first = 415;
  jump.jump = Pose2(0.3, 0.2, 0.6);
  faults.odometry = {jump};
  LaserSlamStats s;
  const double rmse =
      RunBuilding(MakeSyntheticLog(BuildingWorld(false),
                                   BuildingPath(173.0 / 148.0), 51, faults),
                  &s);
  EXPECT_GT(s.global_closures_accepted, 0);
  EXPECT_GT(s.largest_correction_m, 15.0);
  EXPECT_LT(rmse, 0.15);
}

// Issue 24's mechanism on the Freiburg log: the drift of a long excursion
// accumulates through many tight scan matches, each a little wrong, not in
// one weak odometry factor. The laser's field of view is 8 % wider than
// logged: every scan match fits well (tight covariance) but turns by 8 %
// too little, so once round the building (148 m, four corners) the map has
// turned by about 23 deg and the start is revisited 6 m and 23 deg from
// where the map puts it. Closing it bends hundreds of overconfident
// factors a little each: their summed chi2 rises above any fixed bound
// (the old absolute bound undid most closures and the robust kernel
// switched off the few it kept), yet less per link of the chain than a
// wrong closure's. No map can be right with the wrong field of view, so
// the test measures what the Freiburg relations measured: the relative
// pose of each scan of the first 20 m and the scan at the same place one
// lap later (0.020 m mean, 0.051 m worst now, with three global closures;
// 0.57 m while the correlative search's bounds dropped the query points
// sticking out of the place's submap and only local closures closed it).
TEST(LaserSlamTest, RevisitAfterDriftThroughBiasedScanMatchesIsClosed) {
  LogFaults faults;
  faults.turn_steps = 3;
  faults.angle_scale = 1.08;
  const SyntheticLog data = MakeSyntheticLog(
      BuildingWorld(false), BuildingPath(173.0 / 148.0), 71, faults);
  LaserSlam slam{LaserSlamConfig()};
  for (const LaserScan& scan : data.log.scans) slam.AddScan(scan);
  slam.Finish();
  const Trajectory est = slam.ScanTrajectory();
  ASSERT_EQ(est.size(), data.truth.size());
  const size_t lap = BuildingPath(1.0).size();
  double sum = 0.0, worst = 0.0;
  int n = 0;
  for (size_t i = 0; i < 100 && i + lap < est.size(); ++i) {
    const Pose3 e =
        LiftPose2(data.truth[i].Inverse() * data.truth[i + lap]).Inverse() *
        (est[i].pose.Inverse() * est[i + lap].pose);
    sum += e.t.norm();
    worst = std::max(worst, e.t.norm());
    ++n;
  }
  ASSERT_GT(n, 50);
  const LaserSlamStats& s = slam.stats();
  std::printf(
      "revisit relation error %.3f m mean, %.3f m worst; closures %d of %d "
      "accepted (%d global), %d reverted, %d rejected, largest correction "
      "%.2f m %.1f deg\n",
      sum / n, worst, s.closures_accepted, s.closures_proposed,
      s.global_closures_accepted, s.closures_reverted, s.closures_rejected,
      s.largest_correction_m, s.largest_correction_deg);
  EXPECT_GT(s.largest_correction_m, 5.0);
  EXPECT_GT(s.largest_correction_deg, 15.0);
  // The old absolute chi2 bound: 8.8 m mean, 11.4 m worst.
  EXPECT_LT(sum / n, 1.0);
  EXPECT_LT(worst, 1.5);
}

// Two corridors that look the same (BuildingWorld(true)) walked once round
// without a revisit: the global search may propose the one for the other
// and the match may pass, but the closure would turn half of the map by
// 180 deg against every scan match and odometry factor: the chi2 test must
// undo it, and the map stays as tracked.
TEST(LaserSlamTest, LookAlikeCorridorsAreNotClosedOntoEachOther) {
  LogFaults faults;
  faults.turn_steps = 3;
  LaserSlamStats s;
  const double rmse =
      RunBuilding(MakeSyntheticLog(BuildingWorld(true),
                                   BuildingPath(140.0 / 148.0), 61, faults),
                  &s);
  EXPECT_GT(s.global_closures_proposed, 0);  // The aliasing was tried...
  EXPECT_EQ(s.global_closures_accepted, 0);  // ... and nothing kept.
  EXPECT_LT(rmse, 0.3);
}

TEST(LaserSlamTest, RunCommandOnSyntheticLog) {
  const SyntheticLog data = MakeSyntheticLog(1.4, 31);
  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(WriteCarmenLog(dir + "/ring.clf", data.log, &error)) << error;
  testing::WriteText(dir + "/run.yaml",
                     "run:\n  log: ring.clf\n  output_dir: " + dir +
                         "/out\n  map: {resolution: 0.05}\n");
  const std::string log = dir + "/log.txt";
  ASSERT_EQ(RunSlam("run --config " + dir + "/run.yaml --datasets " + dir, log),
            0)
      << testing::ReadText(log);
  const std::string text = testing::ReadText(log);
  EXPECT_TRUE(testing::Contains(text, "keyframes")) << text;
  EXPECT_TRUE(testing::Contains(text, "loop closures:")) << text;
  Trajectory est;
  ASSERT_TRUE(ReadTumTrajectory(dir + "/out/trajectory.tum", &est, &error))
      << error;
  ASSERT_EQ(est.size(), data.truth.size());
  EXPECT_LT(PositionRmse(est, data.truth), 0.05) << text;
  EXPECT_TRUE(testing::Exists(dir + "/out/graph.g2o"));
  EXPECT_TRUE(testing::Exists(dir + "/out/map.pgm"));
  EXPECT_TRUE(testing::Exists(dir + "/out/map.yaml"));
  EXPECT_TRUE(testing::Exists(dir + "/out/map.png"));

  // Bad input: an unknown key, a missing log, a malformed log line.
  testing::WriteText(dir + "/typo.yaml",
                     "run:\n  log: ring.clf\n  keyframe: {}\n");
  EXPECT_NE(RunSlam("run --config " + dir + "/typo.yaml", log), 0);
  EXPECT_TRUE(testing::Contains(testing::ReadText(log), "unknown key"));
  testing::WriteText(dir + "/missing.yaml", "run:\n  log: nothere.clf\n");
  EXPECT_NE(
      RunSlam("run --config " + dir + "/missing.yaml --datasets " + dir, log),
      0);
  testing::WriteText(dir + "/bad.clf",
                     "ODOM 0 0 0 0 0 0 1.0 nohost 1.0\n"
                     "FLASER 3 1.0 2.0 0 0 0 0 0 0 1.1 nohost 1.1\n");
  testing::WriteText(dir + "/bad.yaml", "run:\n  log: bad.clf\n  output_dir: " +
                                            dir + "/bad_out\n");
  EXPECT_NE(RunSlam("run --config " + dir + "/bad.yaml --datasets " + dir, log),
            0);
  EXPECT_TRUE(testing::Contains(testing::ReadText(log), "bad.clf:2"))
      << testing::ReadText(log);
  EXPECT_FALSE(testing::Exists(dir + "/bad_out/trajectory.tum"));
  // --dump_config prints the effective settings, loadable again.
  ASSERT_EQ(RunSlam("run --config " + dir + "/run.yaml --dump_config",
                    dir + "/dump.yaml"),
            0);
  EXPECT_EQ(RunSlam("run --config " + dir + "/dump.yaml --dump_config", log), 0)
      << testing::ReadText(log);
  EXPECT_EQ(testing::ReadText(log), testing::ReadText(dir + "/dump.yaml"));
}

// The real ACES log against its ground-truth relations (Kuemmerle et al.
// 2009), and the sharpness of its map. Bounds a little above what the
// default settings reach (0.0485 m, 0.385 deg mean); Cartographer's
// published figures are 0.0375 m, 0.373 deg.
TEST(LaserSlamTest, AcesRelationError) {
  const std::string log_path = DatasetPath("laser_logs_carmen/aces.clf.bz2");
  const std::string relations_path =
      DatasetPath("laser_logs_carmen/aces.relations");
  SLAM_REQUIRE_DATASET(log_path);
  SLAM_REQUIRE_DATASET(relations_path);
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(ReadCarmenLog(log_path, CarmenReadOptions(), &log, &error))
      << error;
  std::vector<PoseRelation> relations;
  ASSERT_TRUE(ReadRelations(relations_path, &relations, &error)) << error;
  LaserSlam slam{LaserSlamConfig()};
  for (const LaserScan& scan : log.scans) slam.AddScan(scan);
  slam.Finish();
  RelationErrorResult r;
  ASSERT_TRUE(ComputeRelationError(slam.ScanTrajectory(), relations,
                                   RelationErrorOptions(), &r, &error))
      << error;
  EXPECT_EQ(r.used.size(), relations.size());
  // 0.0362 +- 0.0343 m, 0.307 +- 0.286 deg with the defaults (deterministic).
  // The bounds are Cartographer's figures (Hess et al. 2016, Table II).
  EXPECT_LT(r.translation_abs.mean, 0.0375);
  EXPECT_LT(r.translation_abs.std, 0.0426);
  EXPECT_LT(r.rotation_abs.mean, 0.373);
  EXPECT_LT(r.rotation_abs.std, 0.469);
  EXPECT_GT(slam.stats().closures_accepted, 50);
  // A sharp map: few cells with mixed evidence along the walls (26% of
  // mixed + occupied with the defaults; 36% without loop closures).
  OccupancyGrid grid{OccupancyGridConfig()};
  InsertKeyframeScans(slam, log.scans, &grid);
  const MapSharpness sharpness = MeasureSharpness(grid);
  EXPECT_LT(sharpness.MixedFraction(), 0.30);
  EXPECT_GT(sharpness.occupied, 10000u);
  std::printf(
      "ACES: translation %.4f +- %.4f m, rotation %.3f +- %.3f deg, mixed "
      "%.3f\n",
      r.translation_abs.mean, r.translation_abs.std, r.rotation_abs.mean,
      r.rotation_abs.std, sharpness.MixedFraction());
}

}  // namespace
}  // namespace slam
