// A 2D occupancy grid with log-odds updates, built from laser scans at known
// poses, and its output in the format ROS map_server reads (PGM + YAML).
//
// Cells are squares of `resolution` metres; cell (ix, iy) covers
// [ix * res, (ix + 1) * res) x [iy * res, (iy + 1) * res) in the world frame,
// so cell indices are global and the grid grows (by doubling) in any direction
// as scans reach new cells.
//
// InsertScan traces every usable beam from the laser position to its endpoint
// with Bresenham's line over the cells. Within one scan a cell is updated at
// most once: endpoint cells get l_occ (hits first), then the cells the beams
// cross get l_free unless they were hit by this scan; the result is clamped to
// [l_min, l_max]. Beams:
//   - range < min_range, or not finite: skipped;
//   - range >= scan.max_range (no return): with clear_max_range the cells up
//     to max_usable_range along the beam are made free (no hit), else the beam
//     is skipped;
//   - range > max_usable_range: the beam clears up to max_usable_range, no
//     hit (far readings are too noisy in angle to mark cells);
//   - otherwise: free cells up to the endpoint, the endpoint cell occupied.
// Cell states use the map_server thresholds on p = 1 - 1 / (1 + exp(l)):
// occupied if p > occupied_thresh, free if p < free_thresh, else unknown
// (cells never observed are unknown).
#ifndef SLAM_FRONTENDS_OCCUPANCY_GRID_H_
#define SLAM_FRONTENDS_OCCUPANCY_GRID_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/lie.h"
#include "datasets/carmen_io.h"

namespace slam {

struct OccupancyGridConfig {
  double resolution = 0.05;  // Metres per cell.
  double l_occ = 0.85;       // Added at a hit (p = 0.7).
  double l_free = -0.4;      // Added along a beam (p = 0.4).
  double l_min = -2.0;       // Clamp bounds of the log-odds.
  double l_max = 3.5;
  double min_range = 0.05;         // Shorter readings are skipped.
  double max_usable_range = 30.0;  // Beyond: clear only, no hit.
  bool clear_max_range = true;     // No-return readings clear (see above).
  // Thresholds on the occupancy probability, written into the YAML.
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  // Largest grid (cells, 8 bytes each): a scan that would make the grid
  // larger (e.g. at a wildly wrong pose) is refused.
  int64_t max_cells = 100000000;
};

// False with a message naming the first bad field.
bool CheckOccupancyGridConfig(const OccupancyGridConfig& config,
                              std::string* error);

enum class CellState { kUnknown, kFree, kOccupied };

// An 8-bit map image in map_server's trinary convention: 0 occupied, 254
// free, 205 unknown; row 0 is the top (largest y). origin_x, origin_y: the
// world position of the lower-left corner of the lower-left pixel.
struct MapImage {
  int width = 0;
  int height = 0;
  double resolution = 0.0;
  double origin_x = 0.0;
  double origin_y = 0.0;
  std::vector<uint8_t> pixels;  // Row-major, width * height.

  uint8_t at(int row, int col) const { return pixels[row * width + col]; }
};

constexpr uint8_t kPixelOccupied = 0;
constexpr uint8_t kPixelFree = 254;
constexpr uint8_t kPixelUnknown = 205;

class OccupancyGrid {
 public:
  explicit OccupancyGrid(const OccupancyGridConfig& config = {});

  // Adds one scan taken with the laser at `laser_pose` (world frame; for a
  // robot pose x: x * scan.laser_offset). False (and nothing changed) when
  // the pose is not finite or the grid would exceed config.max_cells.
  bool InsertScan(const Pose2& laser_pose, const LaserScan& scan);

  // Cell index of a world point.
  int64_t CellIndex(double coordinate) const;
  // Log-odds of the cell holding (x, y); 0 outside the grid.
  double LogOdds(double x, double y) const;
  CellState State(double x, double y) const;
  bool Observed(double x, double y) const;

  // The bounding box of the observed cells as a map image (empty image, 0 x
  // 0, when nothing was observed).
  MapImage ToImage() const;

  const OccupancyGridConfig& config() const { return config_; }
  int scans_inserted() const { return scans_inserted_; }

 private:
  // Makes cells [x0, x1] x [y0, y1] (global indices) part of the storage;
  // false when that would take more than config.max_cells.
  bool Grow(int64_t x0, int64_t y0, int64_t x1, int64_t y1);
  // Storage index of a global cell, or -1 outside.
  int64_t Offset(int64_t ix, int64_t iy) const;
  CellState StateOf(int64_t offset) const;

  OccupancyGridConfig config_;
  int64_t min_ix_ = 0;  // Global index of storage column 0.
  int64_t min_iy_ = 0;
  int64_t width_ = 0;
  int64_t height_ = 0;
  std::vector<float> log_odds_;
  // Number of the last scan that updated the cell (0: never observed).
  std::vector<uint32_t> last_scan_;
  uint32_t scan_counter_ = 0;
  int scans_inserted_ = 0;
};

// Writes `image` as a binary PGM (P5, maxval 255) and the YAML that
// map_server reads (image: the PGM's file name, relative to the YAML when in
// the same folder; resolution; origin [x, y, 0]; negate 0; the thresholds of
// `config`). Both through a temporary file and a rename; "PATH: problem".
bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const MapImage& image, const OccupancyGridConfig& config,
                     std::string* error);

// Reads a binary PGM (P5, maxval <= 255, '#' comments in the header) into
// image->pixels, width and height (resolution and origin untouched).
bool ReadPgm(const std::string& path, MapImage* image, std::string* error);

}  // namespace slam

#endif  // SLAM_FRONTENDS_OCCUPANCY_GRID_H_
