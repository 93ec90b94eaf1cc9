// A 2D occupancy grid with log-odds updates, built from laser scans at known
// poses, and its output in the format ROS map_server reads (PGM + YAML).
//
// Cells are squares of `resolution` metres; cell (ix, iy) covers
// [ix * res, (ix + 1) * res) x [iy * res, (iy + 1) * res) in the world frame,
// so cell indices are global and the map extends in any direction as scans
// reach new cells. Storage is tiled: square tiles of kTileSide x kTileSide
// cells are allocated when a scan first touches one of their cells, so the
// memory is proportional to the observed area (plus one pointer per tile of
// the bounding box), not to the bounding box: a drifted trajectory that
// spreads a few scans over a large area costs the cells those scans saw.
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
#ifndef SLAM_FRONTENDS_LASER_OCCUPANCY_GRID_H_
#define SLAM_FRONTENDS_LASER_OCCUPANCY_GRID_H_

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/lie.h"
#include "core/sensors/laser_data.h"

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
  // Largest map extent (cells of the bounding box of the touched tiles; the
  // full-resolution PGM has one byte per cell): a scan that would make the
  // extent larger (e.g. at a wildly wrong pose) is refused.
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

// One pixel for several cells (a map drawn coarser than its cells):
// occupied wins over free, free over unknown.
inline uint8_t MergeMapPixels(uint8_t a, uint8_t b) {
  if (a == kPixelOccupied || b == kPixelOccupied) return kPixelOccupied;
  if (a == kPixelFree || b == kPixelFree) return kPixelFree;
  return kPixelUnknown;
}

class OccupancyGrid {
 public:
  // Side of a storage tile, in cells.
  static constexpr int kTileSide = 64;

  explicit OccupancyGrid(const OccupancyGridConfig& config = {});

  // Adds one scan taken with the laser at `laser_pose` (world frame; for a
  // robot pose x: x * scan.laser_offset). False (and nothing changed) when
  // the pose is not finite or the map extent would exceed config.max_cells.
  // Each beam costs at most max_usable_range / resolution cell updates.
  bool InsertScan(const Pose2& laser_pose, const LaserScan& scan);

  // Cell index of a world point.
  int64_t CellIndex(double coordinate) const;
  // Log-odds of the cell holding (x, y); 0 outside the grid.
  double LogOdds(double x, double y) const;
  CellState State(double x, double y) const;
  bool Observed(double x, double y) const;
  // The state of an observed cell with these log-odds (the thresholds).
  CellState StateOf(double log_odds) const;

  // Calls visit(ix, iy, log_odds) for every observed cell (global indices),
  // tile by tile; cost proportional to the allocated cells.
  template <typename Visit>
  void ForEachObservedCell(Visit visit) const;

  // The bounding box of the observed cells as a map image (empty image, 0 x
  // 0, when nothing was observed). max_side <= 0: one pixel per cell. Else
  // k x k cells make one pixel, k the smallest integer that keeps both sides
  // within max_side (resolution k times the cell size): occupied if any of
  // its cells is, else free if any is, else unknown (MergeMapPixels;
  // apps/plot/map_plot.h DownsampleMapImage does the same to an image). Cost:
  // the pixels plus the allocated cells.
  MapImage ToImage(int max_side = 0) const;

  // Cells of the allocated tiles (memory: 8 bytes each).
  int64_t allocated_cells() const;
  // Columns and rows of the observed bounding box (0 x 0 when empty).
  void ObservedExtent(int64_t* cols, int64_t* rows) const;

  const OccupancyGridConfig& config() const { return config_; }
  int scans_inserted() const { return scans_inserted_; }

 private:
  static constexpr int kTileCells = kTileSide * kTileSide;
  struct Tile {
    std::array<float, kTileCells> log_odds{};
    // Number of the last scan that updated the cell (0: never observed).
    std::array<uint32_t, kTileCells> last_scan{};
  };
  // Inclusive bounds of observed cells (global indices); false when none.
  struct Bounds {
    int64_t x0, y0, x1, y1;
  };
  bool ObservedBounds(Bounds* bounds) const;
  // Renders the observed bounding box with k x k cells per pixel into
  // `pixels` (rows of `width` bytes, top row first).
  void Render(const Bounds& bounds, int64_t k, int64_t width, int64_t height,
              uint8_t* pixels) const;
  // Makes tiles [tx0, tx1] x [ty0, ty1] addressable in the directory; false
  // when the extent would exceed config.max_cells.
  bool Reserve(int64_t tx0, int64_t ty0, int64_t tx1, int64_t ty1);
  // The tile holding a cell, or nullptr (not allocated or outside).
  const Tile* TileOf(int64_t ix, int64_t iy) const;

  friend bool WriteMapPgmYaml(const std::string&, const std::string&,
                              const OccupancyGrid&, std::string*);

  OccupancyGridConfig config_;
  // Tile directory: tiles [tile_x0_, tile_x0_ + tiles_w_) x [tile_y0_, ...),
  // row-major, nullptr where no cell was touched.
  int64_t tile_x0_ = 0;
  int64_t tile_y0_ = 0;
  int64_t tiles_w_ = 0;
  int64_t tiles_h_ = 0;
  std::vector<std::unique_ptr<Tile>> tiles_;
  int64_t allocated_tiles_ = 0;
  // Extent: the tiles any accepted scan reached (inclusive; empty when
  // extent_x0_ > extent_x1_).
  int64_t extent_x0_ = 0, extent_y0_ = 0, extent_x1_ = -1, extent_y1_ = -1;
  uint32_t scan_counter_ = 0;
  int scans_inserted_ = 0;
};

template <typename Visit>
void OccupancyGrid::ForEachObservedCell(Visit visit) const {
  for (int64_t t = 0; t < static_cast<int64_t>(tiles_.size()); ++t) {
    const Tile* tile = tiles_[t].get();
    if (tile == nullptr) continue;
    const int64_t bx = (tile_x0_ + t % tiles_w_) * kTileSide;
    const int64_t by = (tile_y0_ + t / tiles_w_) * kTileSide;
    for (int i = 0; i < kTileCells; ++i) {
      if (tile->last_scan[i] == 0) continue;
      visit(bx + i % kTileSide, by + i / kTileSide, tile->log_odds[i]);
    }
  }
}

// Writes `image` as a binary PGM (P5, maxval 255) and the YAML that
// map_server reads (image: the PGM's file name, relative to the YAML when in
// the same folder; resolution; origin [x, y, 0]; negate 0; the thresholds of
// `config`). Both through a temporary file and a rename; "PATH: problem".
bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const MapImage& image, const OccupancyGridConfig& config,
                     std::string* error);
// The same for the full-resolution image of `grid`, rendered straight into
// the file's bytes (no image in between: peak memory one byte per cell of
// the bounding box).
bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const OccupancyGrid& grid, std::string* error);

// Reads a binary PGM (P5, maxval <= 255, '#' comments in the header) into
// image->pixels, width and height (resolution and origin untouched).
bool ReadPgm(const std::string& path, MapImage* image, std::string* error);

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_OCCUPANCY_GRID_H_
