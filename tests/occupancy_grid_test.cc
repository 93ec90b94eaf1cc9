// Occupancy grid: exact log-odds updates of single beams, clamping, growth,
// a synthetic room scanned from known poses (walls occupied, interior free,
// outside unknown, the no-return rule through a door), the PGM + YAML output
// read back, the map PNG of the plot module, and costs that follow the
// observed cells (tiled storage, merged pictures) rather than the extent.
#include "frontends/laser/occupancy_grid.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "apps/map_png.h"
#include "apps/plot/map_plot.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::TempDir;

constexpr double kMaxRange = 20.0;

// A closed rectangular room [x0, x1] x [y0, y1] with a door (a gap) in the
// right wall for y in (door_y0, door_y1); nothing outside.
struct Room {
  double x0 = -2.0, x1 = 4.0, y0 = -1.5, y1 = 2.5;
  double door_y0 = 0.0, door_y1 = 0.8;

  // Distance along the ray from p in direction angle to the first wall, or
  // kMaxRange when the ray leaves through the door.
  double Cast(const Eigen::Vector2d& p, double angle) const {
    const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
    double best = kMaxRange;
    const auto vertical = [&](double x, bool has_door) {
      if (std::abs(d.x()) < 1e-12) return;
      const double t = (x - p.x()) / d.x();
      const double y = p.y() + t * d.y();
      if (t <= 0 || y < y0 || y > y1) return;
      if (has_door && y > door_y0 && y < door_y1) return;
      best = std::min(best, t);
    };
    const auto horizontal = [&](double y) {
      if (std::abs(d.y()) < 1e-12) return;
      const double t = (y - p.y()) / d.y();
      const double x = p.x() + t * d.x();
      if (t <= 0 || x < x0 || x > x1) return;
      best = std::min(best, t);
    };
    vertical(x0, false);
    vertical(x1, true);
    horizontal(y0);
    horizontal(y1);
    return best;
  }

  LaserScan Scan(const Pose2& pose, int beams) const {
    LaserScan scan;
    scan.angle_min = -M_PI;
    scan.angle_increment = 2.0 * M_PI / beams;
    scan.max_range = kMaxRange;
    for (int i = 0; i < beams; ++i) {
      scan.ranges.push_back(static_cast<float>(Cast(
          pose.t, pose.theta + scan.angle_min + i * scan.angle_increment)));
    }
    return scan;
  }
};

std::vector<Pose2> RoomPoses() {
  std::vector<Pose2> poses;
  for (double x : {-1.2, 0.0, 1.5, 3.0}) {
    for (double y : {-0.8, 0.5, 1.8}) {
      poses.emplace_back(x, y, 0.3 * x - 0.2 * y);
    }
  }
  return poses;
}

OccupancyGrid BuildRoom(const Room& room, const OccupancyGridConfig& config) {
  OccupancyGrid grid(config);
  for (const Pose2& pose : RoomPoses()) {
    const LaserScan scan = room.Scan(pose, 720);
    for (int k = 0; k < 2; ++k) grid.InsertScan(pose, scan);
  }
  return grid;
}

// A single-beam scan along the laser's x axis.
LaserScan OneBeam(double range, double max_range = kMaxRange) {
  LaserScan scan;
  scan.angle_min = 0.0;
  scan.angle_increment = 0.01;
  scan.max_range = max_range;
  scan.ranges = {static_cast<float>(range)};
  return scan;
}

TEST(OccupancyGrid, SingleBeamLogOdds) {
  OccupancyGridConfig config;
  OccupancyGrid grid(config);
  const Pose2 pose(0.025, 0.025, 0.0);
  grid.InsertScan(pose, OneBeam(1.0));
  // Cells 0..19 along x are crossed, cell 20 holds the endpoint (1.025).
  for (int i = 0; i < 20; ++i) {
    EXPECT_FLOAT_EQ(grid.LogOdds(0.025 + 0.05 * i, 0.025), config.l_free) << i;
  }
  EXPECT_FLOAT_EQ(grid.LogOdds(1.025, 0.025), config.l_occ);
  EXPECT_FALSE(grid.Observed(1.075, 0.025));
  EXPECT_FALSE(grid.Observed(0.025, 0.075));
  EXPECT_EQ(grid.State(0.5, 0.025), CellState::kUnknown);  // p = 0.4.

  // Clamped after many scans.
  for (int k = 0; k < 20; ++k) grid.InsertScan(pose, OneBeam(1.0));
  EXPECT_FLOAT_EQ(grid.LogOdds(0.5, 0.025), config.l_min);
  EXPECT_FLOAT_EQ(grid.LogOdds(1.025, 0.025), config.l_max);
  EXPECT_EQ(grid.State(0.5, 0.025), CellState::kFree);
  EXPECT_EQ(grid.State(1.025, 0.025), CellState::kOccupied);
  EXPECT_EQ(grid.scans_inserted(), 21);

  // The grid grows in every direction and keeps what it holds.
  grid.InsertScan(Pose2(-40.0, -30.0, 0.0), OneBeam(1.0));
  grid.InsertScan(Pose2(50.0, 60.0, M_PI / 2), OneBeam(2.0));
  EXPECT_FLOAT_EQ(grid.LogOdds(0.5, 0.025), config.l_min);
  EXPECT_FLOAT_EQ(grid.LogOdds(1.025, 0.025), config.l_max);
  EXPECT_FLOAT_EQ(grid.LogOdds(-39.0 + 0.001, -30.0 + 0.001), config.l_occ);
  EXPECT_FLOAT_EQ(grid.LogOdds(50.0 + 0.001, 62.0 + 0.001), config.l_occ);
  EXPECT_FLOAT_EQ(grid.LogOdds(50.0 + 0.001, 61.0), config.l_free);
}

TEST(OccupancyGrid, BeamRules) {
  OccupancyGridConfig config;
  config.max_usable_range = 2.0;
  config.min_range = 0.1;
  {
    // A no-return reading clears up to max_usable_range, marks nothing.
    OccupancyGrid grid(config);
    grid.InsertScan(Pose2(0.025, 0.025, 0.0), OneBeam(kMaxRange));
    EXPECT_FLOAT_EQ(grid.LogOdds(1.0, 0.025), config.l_free);
    EXPECT_FLOAT_EQ(grid.LogOdds(2.0, 0.025), config.l_free);
    EXPECT_FALSE(grid.Observed(2.2, 0.025));
  }
  {
    // A reading beyond the usable range, below max_range: the same.
    OccupancyGrid grid(config);
    grid.InsertScan(Pose2(0.025, 0.025, 0.0), OneBeam(5.0));
    EXPECT_FLOAT_EQ(grid.LogOdds(2.0, 0.025), config.l_free);
    EXPECT_FALSE(grid.Observed(5.025, 0.025));
  }
  {
    // Without clear_max_range no-return readings are skipped.
    config.clear_max_range = false;
    OccupancyGrid grid(config);
    grid.InsertScan(Pose2(0.025, 0.025, 0.0), OneBeam(kMaxRange));
    EXPECT_FALSE(grid.Observed(1.0, 0.025));
    // As are readings below min_range and non-finite ones.
    grid.InsertScan(Pose2(0.025, 0.025, 0.0), OneBeam(0.05));
    grid.InsertScan(Pose2(0.025, 0.025, 0.0),
                    OneBeam(std::numeric_limits<double>::quiet_NaN()));
    EXPECT_FALSE(grid.Observed(0.025, 0.025));
    EXPECT_TRUE(grid.ToImage().pixels.empty());
  }
  {
    // Within one scan a cell is updated once, and a hit wins over a pass.
    OccupancyGrid grid(OccupancyGridConfig{});
    LaserScan scan = OneBeam(1.0);
    scan.ranges = {1.0f, 1.0f, 0.5f};
    scan.angle_increment = 0.0;  // Three beams along the same line.
    grid.InsertScan(Pose2(0.025, 0.025, 0.0), scan);
    EXPECT_FLOAT_EQ(grid.LogOdds(0.2, 0.025), OccupancyGridConfig{}.l_free);
    EXPECT_FLOAT_EQ(grid.LogOdds(0.525, 0.025), OccupancyGridConfig{}.l_occ);
    EXPECT_FLOAT_EQ(grid.LogOdds(1.025, 0.025), OccupancyGridConfig{}.l_occ);
  }
}

TEST(OccupancyGrid, RefusesBadPosesAndHugeGrids) {
  OccupancyGridConfig config;
  // An extent of at most 20 tiles (of 64 x 64 cells at 0.05 m, 3.2 m).
  constexpr int64_t kTile = OccupancyGrid::kTileSide;
  config.max_cells = 20 * kTile * kTile;
  OccupancyGrid grid(config);
  EXPECT_TRUE(grid.InsertScan(Pose2(0.025, 0.025, 0.0), OneBeam(1.0)));
  const MapImage before = grid.ToImage();
  // 1 km away: far more cells than allowed.
  EXPECT_FALSE(grid.InsertScan(Pose2(1000.0, 0.0, 0.0), OneBeam(1.0)));
  EXPECT_FALSE(grid.InsertScan(
      Pose2(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), OneBeam(1.0)));
  EXPECT_FALSE(grid.InsertScan(Pose2(1e300, 0.0, 0.0), OneBeam(1.0)));
  // A hit in cell 1280 (tile 20): tiles 0 .. 20 are 21 tiles, one too many.
  EXPECT_FALSE(grid.InsertScan(Pose2(63.001, 0.001, 0.0), OneBeam(1.0)));
  EXPECT_EQ(grid.scans_inserted(), 1);
  const MapImage after = grid.ToImage();
  EXPECT_EQ(after.pixels, before.pixels);
  EXPECT_EQ(after.origin_x, before.origin_x);
  // A hit in cell 1279 (tile 19, the beam from cell 1259): 20 tiles fit.
  EXPECT_TRUE(grid.InsertScan(Pose2(62.951, 0.001, 0.0), OneBeam(1.0)));
  EXPECT_FLOAT_EQ(grid.LogOdds(63.951, 0.001), config.l_occ);
  EXPECT_FLOAT_EQ(grid.LogOdds(1.025, 0.025), config.l_occ);
  EXPECT_EQ(grid.scans_inserted(), 2);
}

// A drifted trajectory: a few scans spread over a large area. The memory of
// the grid follows the cells the scans saw, not their bounding box, and the
// picture of the map stays within the side it is asked for.
TEST(OccupancyGrid, CostFollowsObservedCellsNotExtent) {
  const Room room;
  OccupancyGrid grid{OccupancyGridConfig{}};
  const LaserScan scan = room.Scan(Pose2(0.0, 0.0, 0.0), 720);
  // The room seen from three places up to 400 m apart: 8000 x 4000 cells
  // (within the default max_cells, 1e8).
  const std::vector<Pose2> places = {
      Pose2(0.0, 0.0, 0.0), Pose2(400.0, 0.0, 0.0), Pose2(200.0, 200.0, 0.0)};
  for (const Pose2& place : places) ASSERT_TRUE(grid.InsertScan(place, scan));
  int64_t observed = 0;
  grid.ForEachObservedCell([&](int64_t, int64_t, float) { ++observed; });
  int64_t cols = 0, rows = 0;
  grid.ObservedExtent(&cols, &rows);
  EXPECT_GT(cols, 8000);
  EXPECT_GT(rows, 4000);
  // Each scan sees the room and the wedge through the door (to 20 m): a few
  // tiles each (62706 cells seen, 61 tiles of 4096), however far apart the
  // places are; a dense grid over the box would take 35.8 million cells.
  EXPECT_GT(observed, 3 * 20000);
  EXPECT_LE(grid.allocated_cells(), 8 * observed);
  EXPECT_LT(grid.allocated_cells(), cols * rows / 100);

  const MapImage picture = grid.ToImage(4096);
  EXPECT_LE(picture.width, 4096);
  EXPECT_LE(picture.height, 4096);
  EXPECT_GT(picture.width, 2048);  // No coarser than needed.
  const int64_t k = (cols + 4095) / 4096;
  EXPECT_DOUBLE_EQ(picture.resolution, k * grid.config().resolution);
  // A wall cell of every place is an occupied pixel.
  for (const Pose2& place : places) {
    const double x = place.t.x() + room.x0 + 0.01;
    const double y = place.t.y() + 0.5 * (room.y0 + room.y1);
    ASSERT_EQ(grid.State(x, y), CellState::kOccupied);
    const int col =
        static_cast<int>((x - picture.origin_x) / picture.resolution);
    const int row =
        picture.height - 1 -
        static_cast<int>((y - picture.origin_y) / picture.resolution);
    EXPECT_EQ(picture.at(row, col), kPixelOccupied);
  }
}

// The merged picture follows its rule exactly: a pixel is occupied if any of
// its k x k cells is, else free if any is, else unknown; blocks are counted
// from the origin (lower-left). The same rule on an image (the plot module's
// DownsampleMapImage) gives the same picture.
TEST(OccupancyGrid, MergedPictureRule) {
  const Room room;
  const OccupancyGrid grid = BuildRoom(room, OccupancyGridConfig{});
  const MapImage full = grid.ToImage();
  for (const int max_side : {1000, 100, 37, 10}) {
    const MapImage merged = grid.ToImage(max_side);
    const int k = (std::max(full.width, full.height) + max_side - 1) / max_side;
    ASSERT_EQ(merged.width, (full.width + k - 1) / k) << max_side;
    ASSERT_EQ(merged.height, (full.height + k - 1) / k) << max_side;
    EXPECT_EQ(merged.origin_x, full.origin_x);
    EXPECT_EQ(merged.origin_y, full.origin_y);
    EXPECT_DOUBLE_EQ(merged.resolution, k * full.resolution);
    for (int r = 0; r < merged.height; ++r) {
      for (int c = 0; c < merged.width; ++c) {
        bool occupied = false, free = false;
        // Block rows counted from the bottom of the full image.
        for (int br = 0; br < k; ++br) {
          const int from_bottom = (merged.height - 1 - r) * k + br;
          const int fr = full.height - 1 - from_bottom;
          if (fr < 0) continue;
          for (int bc = 0; bc < k && c * k + bc < full.width; ++bc) {
            const uint8_t p = full.at(fr, c * k + bc);
            occupied |= p == kPixelOccupied;
            free |= p == kPixelFree;
          }
        }
        const uint8_t want = occupied ? kPixelOccupied
                             : free   ? kPixelFree
                                      : kPixelUnknown;
        ASSERT_EQ(merged.at(r, c), want) << max_side << " " << r << " " << c;
      }
    }
    const MapImage again = DownsampleMapImage(full, max_side);
    EXPECT_EQ(again.pixels, merged.pixels) << max_side;
    EXPECT_EQ(again.width, merged.width);
    EXPECT_DOUBLE_EQ(again.resolution, merged.resolution);
  }
  // Fits already: unchanged.
  EXPECT_EQ(grid.ToImage(full.width + full.height).pixels, full.pixels);
  EXPECT_EQ(DownsampleMapImage(full, full.width + full.height).pixels,
            full.pixels);
}

TEST(OccupancyGrid, ConfigChecks) {
  std::string error;
  EXPECT_TRUE(CheckOccupancyGridConfig(OccupancyGridConfig{}, &error));
  OccupancyGridConfig bad;
  bad.resolution = 0.0;
  EXPECT_FALSE(CheckOccupancyGridConfig(bad, &error));
  EXPECT_EQ(error, "occupancy grid: resolution must be > 0");
  bad = OccupancyGridConfig{};
  bad.l_free = 0.4;
  EXPECT_FALSE(CheckOccupancyGridConfig(bad, &error));
  EXPECT_EQ(error, "occupancy grid: l_free must be < 0");
  bad = OccupancyGridConfig{};
  bad.occupied_thresh = 0.1;
  EXPECT_FALSE(CheckOccupancyGridConfig(bad, &error));
  EXPECT_EQ(error,
            "occupancy grid: occupied_thresh must be in (free_thresh, 1)");
}

// Fractions of wall points seen occupied (within one cell) and of interior
// points seen free.
void CheckRoom(const Room& room, const OccupancyGrid& grid) {
  const double res = grid.config().resolution;
  int wall_points = 0, wall_occupied = 0;
  const auto wall_point = [&](double x, double y) {
    ++wall_points;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        if (grid.State(x + dx * res, y + dy * res) == CellState::kOccupied) {
          ++wall_occupied;
          return;
        }
      }
    }
  };
  for (double x = room.x0 + 0.1; x < room.x1 - 0.1; x += 0.05) {
    wall_point(x, room.y0);
    wall_point(x, room.y1);
  }
  for (double y = room.y0 + 0.1; y < room.y1 - 0.1; y += 0.05) {
    wall_point(room.x0, y);
    if (y < room.door_y0 - 0.1 || y > room.door_y1 + 0.1) {
      wall_point(room.x1, y);
    }
  }
  EXPECT_GE(wall_occupied, 0.97 * wall_points)
      << wall_occupied << " of " << wall_points;

  int inside = 0, inside_free = 0, inside_occupied = 0;
  for (double x = room.x0 + 0.2; x < room.x1 - 0.2; x += 0.05) {
    for (double y = room.y0 + 0.2; y < room.y1 - 0.2; y += 0.05) {
      ++inside;
      const CellState state = grid.State(x, y);
      inside_free += state == CellState::kFree;
      inside_occupied += state == CellState::kOccupied;
    }
  }
  EXPECT_GE(inside_free, 0.97 * inside) << inside_free << " of " << inside;
  EXPECT_EQ(inside_occupied, 0);

  // Behind the walls nothing was seen (nor seen through the door).
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(room.x0 - 1.0, 0.5),
        Eigen::Vector2d(1.0, room.y1 + 1.0),
        Eigen::Vector2d(1.0, room.y0 - 0.5),
        Eigen::Vector2d(room.x1 + 1.0, room.y1 + 0.5)}) {
    EXPECT_FALSE(grid.Observed(p.x(), p.y())) << p.transpose();
    EXPECT_EQ(grid.State(p.x(), p.y()), CellState::kUnknown);
  }
}

TEST(OccupancyGrid, SyntheticRoom) {
  const Room room;
  const OccupancyGrid grid = BuildRoom(room, OccupancyGridConfig{});
  CheckRoom(room, grid);
  // Beams through the door cleared the outside up to the usable range.
  EXPECT_EQ(grid.State(room.x1 + 2.0, 0.4), CellState::kFree);

  OccupancyGridConfig skip;
  skip.clear_max_range = false;
  const OccupancyGrid grid_skip = BuildRoom(room, skip);
  CheckRoom(room, grid_skip);
  EXPECT_FALSE(grid_skip.Observed(room.x1 + 2.0, 0.4));
}

TEST(OccupancyGrid, PgmYamlRoundTrip) {
  const Room room;
  OccupancyGridConfig config;
  config.resolution = 0.1;
  config.clear_max_range = false;
  const OccupancyGrid grid = BuildRoom(room, config);
  const MapImage image = grid.ToImage();
  ASSERT_GT(image.width, 0);
  // The observed box is the room (walls included), to a cell.
  EXPECT_NEAR(image.origin_x, room.x0, 0.1 + 1e-9);
  EXPECT_NEAR(image.origin_y, room.y0, 0.1 + 1e-9);
  EXPECT_NEAR(image.origin_x + image.width * 0.1, room.x1, 0.1 + 1e-9);
  EXPECT_NEAR(image.origin_y + image.height * 0.1, room.y1, 0.1 + 1e-9);

  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(WriteMapPgmYaml(dir + "/map.pgm", dir + "/map.yaml", image,
                              config, &error))
      << error;
  MapImage back;
  ASSERT_TRUE(ReadPgm(dir + "/map.pgm", &back, &error)) << error;
  EXPECT_EQ(back.width, image.width);
  EXPECT_EQ(back.height, image.height);
  EXPECT_EQ(back.pixels, image.pixels);

  const YAML::Node yaml = YAML::LoadFile(dir + "/map.yaml");
  EXPECT_EQ(yaml["image"].as<std::string>(), "map.pgm");
  EXPECT_EQ(yaml["resolution"].as<double>(), 0.1);
  ASSERT_EQ(yaml["origin"].size(), 3u);
  EXPECT_EQ(yaml["origin"][0].as<double>(), image.origin_x);
  EXPECT_EQ(yaml["origin"][1].as<double>(), image.origin_y);
  EXPECT_EQ(yaml["origin"][2].as<double>(), 0.0);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_EQ(yaml["free_thresh"].as<double>(), 0.196);

  // Pixels read back, placed the way map_server places them (origin at the
  // lower-left pixel, row 0 at the top), agree with the grid everywhere.
  int occupied = 0;
  for (int row = 0; row < back.height; ++row) {
    for (int col = 0; col < back.width; ++col) {
      const double x = image.origin_x + (col + 0.5) * 0.1;
      const double y = image.origin_y + (back.height - row - 0.5) * 0.1;
      const CellState state = grid.State(x, y);
      const uint8_t expected = state == CellState::kOccupied ? kPixelOccupied
                               : state == CellState::kFree   ? kPixelFree
                                                             : kPixelUnknown;
      ASSERT_EQ(back.at(row, col), expected) << row << " " << col;
      occupied += state == CellState::kOccupied;
      // map_server's reading of the value gives the same class.
      const double p = (255.0 - back.at(row, col)) / 255.0;
      const CellState ros = p > 0.65    ? CellState::kOccupied
                            : p < 0.196 ? CellState::kFree
                                        : CellState::kUnknown;
      ASSERT_EQ(ros, state);
    }
  }
  EXPECT_GT(occupied, 100);

  // The YAML names the PGM by its absolute path when in another folder.
  std::filesystem::create_directories(dir + "/sub");
  ASSERT_TRUE(WriteMapPgmYaml(dir + "/map.pgm", dir + "/sub/map.yaml", image,
                              config, &error));
  EXPECT_EQ(YAML::LoadFile(dir + "/sub/map.yaml")["image"].as<std::string>(),
            std::filesystem::absolute(dir + "/map.pgm").string());

  // Bad PGM input.
  testing::WriteText(dir + "/bad.pgm", "P2\n2 2\n255\n0 0 0 0\n");
  EXPECT_FALSE(ReadPgm(dir + "/bad.pgm", &back, &error));
  EXPECT_EQ(error, dir + "/bad.pgm: not a binary PGM (no P5 magic)");
  testing::WriteText(dir + "/bad.pgm", "P5\n# c\n4 4\n255\nabc");
  EXPECT_FALSE(ReadPgm(dir + "/bad.pgm", &back, &error));
  EXPECT_TRUE(testing::Contains(error, "truncated PGM")) << error;
  EXPECT_FALSE(WriteMapPgmYaml(dir + "/e.pgm", dir + "/e.yaml", MapImage(),
                               config, &error));
  EXPECT_FALSE(testing::Exists(dir + "/e.pgm"));
}

TEST(OccupancyGrid, MapPngWithTrajectory) {
  const Room room;
  const OccupancyGrid grid = BuildRoom(room, OccupancyGridConfig{});
  const MapImage image = grid.ToImage();
  std::vector<Eigen::Vector2d> trajectory;
  for (const Pose2& p : RoomPoses()) trajectory.push_back(p.t);
  const cv::Mat png = RenderMapImage(image, trajectory, 1);
  ASSERT_EQ(png.cols, image.width);
  ASSERT_EQ(png.rows, image.height);
  // A wall cell is black, an interior cell away from the path light, a point
  // of the path in the trajectory colour.
  const auto pixel = [&](double x, double y) {
    const int col = static_cast<int>((x - image.origin_x) / image.resolution);
    const int row = image.height - 1 -
                    static_cast<int>((y - image.origin_y) / image.resolution);
    return png.at<cv::Vec3b>(row, col);
  };
  const Pose2 start = RoomPoses().front();
  const cv::Vec3b on_path = pixel(start.t.x(), start.t.y());
  EXPECT_NE(on_path, cv::Vec3b(254, 254, 254));
  EXPECT_NE(on_path, cv::Vec3b(0, 0, 0));
  const std::string path = TempDir() + "/map.png";
  std::string error;
  ASSERT_TRUE(WriteMapPngImpl(path, image, trajectory, &error)) << error;
  EXPECT_GT(testing::ReadText(path).size(), 100u);
}

// A map image larger than the picture's bound (e.g. from a drifted run) is
// drawn merged down to kMapPngMaxSide pixels on its long side.
TEST(OccupancyGrid, MapPngSizeBounded) {
  MapImage image;
  image.width = 3 * kMapPngMaxSide + 5;
  image.height = 7;
  image.resolution = 0.05;
  image.pixels.assign(static_cast<size_t>(image.width) * image.height,
                      kPixelFree);
  const std::string path = TempDir() + "/wide.png";
  std::string error;
  ASSERT_TRUE(WriteMapPngImpl(path, image, {}, &error)) << error;
  const std::string png = testing::ReadText(path);
  ASSERT_GT(png.size(), 24u);
  // IHDR: width and height, big-endian, at bytes 16 and 20.
  const auto u32 = [&](size_t at) {
    return (static_cast<uint32_t>(static_cast<uint8_t>(png[at])) << 24) |
           (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 1])) << 16) |
           (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 2])) << 8) |
           static_cast<uint32_t>(static_cast<uint8_t>(png[at + 3]));
  };
  EXPECT_EQ(u32(16), static_cast<uint32_t>((image.width + 3) / 4));
  EXPECT_EQ(u32(20), 2u);
}

}  // namespace
}  // namespace slam
