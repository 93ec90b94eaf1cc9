#include "frontends/laser/occupancy_grid.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string_view>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"

namespace slam {
namespace {

// Tiles added beyond what a scan needs when the tile directory grows (at
// least; only pointers).
constexpr int64_t kGrowMarginTiles = 4;

// floor(a / b) for b > 0.
int64_t FloorDiv(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The tile of a cell index, and the cell's place in its tile.
int64_t TileIndex(int64_t i) { return FloorDiv(i, OccupancyGrid::kTileSide); }
int64_t InTile(int64_t i) {
  return i - TileIndex(i) * OccupancyGrid::kTileSide;
}

// k for a picture of at most max_side pixels on a side (1: full size).
int64_t MergeFactor(int64_t cols, int64_t rows, int max_side) {
  if (max_side <= 0) return 1;
  return std::max<int64_t>(1, (std::max(cols, rows) + max_side - 1) / max_side);
}

uint8_t PixelOf(CellState state) {
  return state == CellState::kOccupied ? kPixelOccupied
         : state == CellState::kFree   ? kPixelFree
                                       : kPixelUnknown;
}

double Probability(double log_odds) {
  return 1.0 - 1.0 / (1.0 + std::exp(log_odds));
}

// Calls visit(ix, iy) for the cells of Bresenham's line from (x0, y0) to
// (x1, y1), the end cell included only if include_end.
template <typename Visit>
void TraceLine(int64_t x0, int64_t y0, int64_t x1, int64_t y1, bool include_end,
               Visit visit) {
  const int64_t dx = std::llabs(x1 - x0);
  const int64_t dy = -std::llabs(y1 - y0);
  const int64_t step_x = x0 < x1 ? 1 : -1;
  const int64_t step_y = y0 < y1 ? 1 : -1;
  int64_t err = dx + dy;
  while (x0 != x1 || y0 != y1) {
    visit(x0, y0);
    const int64_t e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += step_x;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += step_y;
    }
  }
  if (include_end) visit(x1, y1);
}

}  // namespace

bool CheckOccupancyGridConfig(const OccupancyGridConfig& c,
                              std::string* error) {
  struct Rule {
    const char* name;
    bool ok;
    const char* requirement;
  };
  const auto finite = [](double v) { return std::isfinite(v); };
  const Rule rules[] = {
      {"resolution", finite(c.resolution) && c.resolution > 0.0, "> 0"},
      {"l_occ", finite(c.l_occ) && c.l_occ > 0.0, "> 0"},
      {"l_free", finite(c.l_free) && c.l_free < 0.0, "< 0"},
      {"l_min", finite(c.l_min) && c.l_min < 0.0, "< 0"},
      {"l_max", finite(c.l_max) && c.l_max > 0.0, "> 0"},
      {"min_range", finite(c.min_range) && c.min_range >= 0.0, ">= 0"},
      {"max_usable_range",
       finite(c.max_usable_range) && c.max_usable_range > c.min_range,
       "> min_range"},
      {"free_thresh", finite(c.free_thresh) && c.free_thresh > 0.0,
       "in (0, occupied_thresh)"},
      {"max_cells", c.max_cells > 0, "> 0"},
      {"occupied_thresh",
       finite(c.occupied_thresh) && c.occupied_thresh > c.free_thresh &&
           c.occupied_thresh < 1.0,
       "in (free_thresh, 1)"},
  };
  for (const Rule& rule : rules) {
    if (!rule.ok) {
      *error = std::string("occupancy grid: ") + rule.name + " must be " +
               rule.requirement;
      return false;
    }
  }
  // One scan of the usable range must fit in the grid: otherwise the map
  // cannot hold a single scan and the run would fail after all its work.
  // In whole tiles: a scan's box of cells can straddle one more tile.
  const double side = (std::floor(2.0 * c.max_usable_range / c.resolution /
                                  OccupancyGrid::kTileSide) +
                       2.0) *
                      OccupancyGrid::kTileSide;
  if (side * side > static_cast<double>(c.max_cells)) {
    char text[256];
    std::snprintf(text, sizeof(text),
                  "occupancy grid: resolution %g m is too fine: one scan of "
                  "max_usable_range %g m needs %.3g cells, more than max_cells "
                  "(%lld)",
                  c.resolution, c.max_usable_range, side * side,
                  static_cast<long long>(c.max_cells));
    *error = text;
    return false;
  }
  return true;
}

OccupancyGrid::OccupancyGrid(const OccupancyGridConfig& config)
    : config_(config) {}

int64_t OccupancyGrid::CellIndex(double coordinate) const {
  // Saturated (NaN to the low end) so that the conversion is defined; such
  // cells are far outside any grid that fits in memory (max_cells).
  constexpr double kLimit = 4e18;
  const double f = std::floor(coordinate / config_.resolution);
  if (!(f > -kLimit)) return static_cast<int64_t>(-kLimit);
  if (f > kLimit) return static_cast<int64_t>(kLimit);
  return static_cast<int64_t>(f);
}

const OccupancyGrid::Tile* OccupancyGrid::TileOf(int64_t ix, int64_t iy) const {
  const int64_t tx = TileIndex(ix) - tile_x0_;
  const int64_t ty = TileIndex(iy) - tile_y0_;
  if (tx < 0 || ty < 0 || tx >= tiles_w_ || ty >= tiles_h_) return nullptr;
  return tiles_[ty * tiles_w_ + tx].get();
}

bool OccupancyGrid::Reserve(int64_t tx0, int64_t ty0, int64_t tx1,
                            int64_t ty1) {
  // The extent the map would have: limited, the directory is not.
  const bool empty = extent_x0_ > extent_x1_;
  const int64_t ex0 = empty ? tx0 : std::min(tx0, extent_x0_);
  const int64_t ey0 = empty ? ty0 : std::min(ty0, extent_y0_);
  const int64_t ex1 = empty ? tx1 : std::max(tx1, extent_x1_);
  const int64_t ey1 = empty ? ty1 : std::max(ty1, extent_y1_);
  const double cells = static_cast<double>(ex1 - ex0 + 1) *
                       static_cast<double>(ey1 - ey0 + 1) * kTileCells;
  if (cells > static_cast<double>(config_.max_cells)) return false;
  extent_x0_ = ex0;
  extent_y0_ = ey0;
  extent_x1_ = ex1;
  extent_y1_ = ey1;
  if (tiles_w_ > 0 && tx0 >= tile_x0_ && ty0 >= tile_y0_ &&
      tx1 < tile_x0_ + tiles_w_ && ty1 < tile_y0_ + tiles_h_) {
    return true;
  }
  // Grow by at least half the current size on a side that must grow, so
  // that a long run moves the pointers few times.
  const int64_t mx = std::max(kGrowMarginTiles, tiles_w_ / 2);
  const int64_t my = std::max(kGrowMarginTiles, tiles_h_ / 2);
  int64_t nx0 = tx0 - kGrowMarginTiles, ny0 = ty0 - kGrowMarginTiles;
  int64_t nx1 = tx1 + kGrowMarginTiles, ny1 = ty1 + kGrowMarginTiles;
  if (tiles_w_ > 0) {
    const int64_t old_x1 = tile_x0_ + tiles_w_ - 1;
    const int64_t old_y1 = tile_y0_ + tiles_h_ - 1;
    nx0 = tx0 < tile_x0_ ? std::min(nx0, tile_x0_ - mx) : tile_x0_;
    ny0 = ty0 < tile_y0_ ? std::min(ny0, tile_y0_ - my) : tile_y0_;
    nx1 = tx1 > old_x1 ? std::max(nx1, old_x1 + mx) : old_x1;
    ny1 = ty1 > old_y1 ? std::max(ny1, old_y1 + my) : old_y1;
  }
  const int64_t new_w = nx1 - nx0 + 1;
  const int64_t new_h = ny1 - ny0 + 1;
  std::vector<std::unique_ptr<Tile>> tiles(new_w * new_h);
  for (int64_t row = 0; row < tiles_h_; ++row) {
    for (int64_t col = 0; col < tiles_w_; ++col) {
      tiles[(row + tile_y0_ - ny0) * new_w + (col + tile_x0_ - nx0)] =
          std::move(tiles_[row * tiles_w_ + col]);
    }
  }
  tiles_.swap(tiles);
  tile_x0_ = nx0;
  tile_y0_ = ny0;
  tiles_w_ = new_w;
  tiles_h_ = new_h;
  return true;
}

bool OccupancyGrid::InsertScan(const Pose2& laser_pose, const LaserScan& scan) {
  // Far beyond any grid that fits in memory, coordinates cannot become cell
  // indices.
  const double limit = 1e12 * config_.resolution;
  if (!(std::abs(laser_pose.t.x()) < limit) ||
      !(std::abs(laser_pose.t.y()) < limit) ||
      !std::isfinite(laser_pose.theta) || !std::isfinite(scan.angle_min) ||
      !std::isfinite(scan.angle_increment)) {
    return false;
  }
  struct Beam {
    int64_t x;
    int64_t y;
    bool hit;
  };
  std::vector<Beam> beams;
  beams.reserve(scan.ranges.size());
  const int64_t sx = CellIndex(laser_pose.t.x());
  const int64_t sy = CellIndex(laser_pose.t.y());
  int64_t x0 = sx, y0 = sy, x1 = sx, y1 = sy;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r < config_.min_range) continue;
    double length = r;
    bool hit = true;
    if (r >= scan.max_range) {
      if (!config_.clear_max_range) continue;
      length = config_.max_usable_range;
      hit = false;
    } else if (r > config_.max_usable_range) {
      length = config_.max_usable_range;
      hit = false;
    }
    const double angle = laser_pose.theta + scan.angle_min +
                         static_cast<double>(i) * scan.angle_increment;
    const Beam beam{CellIndex(laser_pose.t.x() + length * std::cos(angle)),
                    CellIndex(laser_pose.t.y() + length * std::sin(angle)),
                    hit};
    x0 = std::min(x0, beam.x);
    y0 = std::min(y0, beam.y);
    x1 = std::max(x1, beam.x);
    y1 = std::max(y1, beam.y);
    beams.push_back(beam);
  }
  if (!beams.empty() &&
      !Reserve(TileIndex(x0), TileIndex(y0), TileIndex(x1), TileIndex(y1))) {
    return false;
  }
  ++scans_inserted_;
  if (beams.empty()) return true;
  const uint32_t stamp = ++scan_counter_;
  const auto update = [&](int64_t ix, int64_t iy, double delta) {
    const int64_t tx = TileIndex(ix), ty = TileIndex(iy);
    std::unique_ptr<Tile>& tile =
        tiles_[(ty - tile_y0_) * tiles_w_ + (tx - tile_x0_)];
    if (tile == nullptr) {
      tile = std::make_unique<Tile>();
      ++allocated_tiles_;
    }
    const int64_t o = (iy - ty * kTileSide) * kTileSide + (ix - tx * kTileSide);
    if (tile->last_scan[o] == stamp) return;  // Once per scan; hits first.
    tile->last_scan[o] = stamp;
    tile->log_odds[o] = static_cast<float>(
        std::clamp(static_cast<double>(tile->log_odds[o]) + delta,
                   config_.l_min, config_.l_max));
  };
  for (const Beam& beam : beams) {
    if (beam.hit) update(beam.x, beam.y, config_.l_occ);
  }
  for (const Beam& beam : beams) {
    TraceLine(sx, sy, beam.x, beam.y, !beam.hit,
              [&](int64_t ix, int64_t iy) { update(ix, iy, config_.l_free); });
  }
  return true;
}

double OccupancyGrid::LogOdds(double x, double y) const {
  const int64_t ix = CellIndex(x), iy = CellIndex(y);
  const Tile* tile = TileOf(ix, iy);
  return tile == nullptr ? 0.0
                         : tile->log_odds[InTile(iy) * kTileSide + InTile(ix)];
}

bool OccupancyGrid::Observed(double x, double y) const {
  const int64_t ix = CellIndex(x), iy = CellIndex(y);
  const Tile* tile = TileOf(ix, iy);
  return tile != nullptr &&
         tile->last_scan[InTile(iy) * kTileSide + InTile(ix)] != 0;
}

CellState OccupancyGrid::StateOf(double log_odds) const {
  const double p = Probability(log_odds);
  if (p > config_.occupied_thresh) return CellState::kOccupied;
  if (p < config_.free_thresh) return CellState::kFree;
  return CellState::kUnknown;
}

CellState OccupancyGrid::State(double x, double y) const {
  if (!Observed(x, y)) return CellState::kUnknown;
  return StateOf(LogOdds(x, y));
}

int64_t OccupancyGrid::allocated_cells() const {
  return allocated_tiles_ * kTileCells;
}

void OccupancyGrid::ObservedExtent(int64_t* cols, int64_t* rows) const {
  Bounds b;
  const bool any = ObservedBounds(&b);
  *cols = any ? b.x1 - b.x0 + 1 : 0;
  *rows = any ? b.y1 - b.y0 + 1 : 0;
}

bool OccupancyGrid::ObservedBounds(Bounds* bounds) const {
  Bounds b{
      std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::max(),
      std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::min()};
  ForEachObservedCell([&](int64_t ix, int64_t iy, float) {
    b.x0 = std::min(b.x0, ix);
    b.x1 = std::max(b.x1, ix);
    b.y0 = std::min(b.y0, iy);
    b.y1 = std::max(b.y1, iy);
  });
  if (b.x1 < b.x0) return false;
  *bounds = b;
  return true;
}

void OccupancyGrid::Render(const Bounds& bounds, int64_t k, int64_t width,
                           int64_t height, uint8_t* pixels) const {
  std::fill_n(pixels, width * height, kPixelUnknown);
  ForEachObservedCell([&](int64_t ix, int64_t iy, float log_odds) {
    const int64_t col = (ix - bounds.x0) / k;
    const int64_t row = height - 1 - (iy - bounds.y0) / k;  // Top: largest y.
    uint8_t& pixel = pixels[row * width + col];
    pixel = MergeMapPixels(pixel, PixelOf(StateOf(log_odds)));
  });
}

MapImage OccupancyGrid::ToImage(int max_side) const {
  MapImage image;
  image.resolution = config_.resolution;
  Bounds b;
  if (!ObservedBounds(&b)) return image;
  const int64_t cols = b.x1 - b.x0 + 1, rows = b.y1 - b.y0 + 1;
  const int64_t k = MergeFactor(cols, rows, max_side);
  image.width = static_cast<int>((cols + k - 1) / k);
  image.height = static_cast<int>((rows + k - 1) / k);
  image.resolution = config_.resolution * static_cast<double>(k);
  image.origin_x = static_cast<double>(b.x0) * config_.resolution;
  image.origin_y = static_cast<double>(b.y0) * config_.resolution;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height);
  Render(b, k, image.width, image.height, image.pixels.data());
  return image;
}

namespace {

// The map_server YAML of an image written as `pgm_path`.
std::string MapYaml(const std::string& pgm_path, const std::string& yaml_path,
                    double resolution, double origin_x, double origin_y,
                    const OccupancyGridConfig& config) {
  namespace fs = std::filesystem;
  const fs::path pgm_file(pgm_path);
  const fs::path yaml_file(yaml_path);
  const std::string image_name = fs::absolute(pgm_file).parent_path() ==
                                         fs::absolute(yaml_file).parent_path()
                                     ? pgm_file.filename().string()
                                     : fs::absolute(pgm_file).string();
  std::string yaml = "image: " + image_name + "\nresolution: ";
  text::AppendDouble(resolution, &yaml);
  yaml += "\norigin: [";
  text::AppendDouble(origin_x, &yaml);
  yaml += ", ";
  text::AppendDouble(origin_y, &yaml);
  yaml += ", 0.0]\nnegate: 0\noccupied_thresh: ";
  text::AppendDouble(config.occupied_thresh, &yaml);
  yaml += "\nfree_thresh: ";
  text::AppendDouble(config.free_thresh, &yaml);
  yaml += "\n";
  return yaml;
}

std::string PgmHeader(int64_t width, int64_t height) {
  return "P5\n" + std::to_string(width) + " " + std::to_string(height) +
         "\n255\n";
}

}  // namespace

bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const MapImage& image, const OccupancyGridConfig& config,
                     std::string* error) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height) {
    *error = pgm_path + ": empty map (no scan observed any cell)";
    return false;
  }
  std::string pgm = PgmHeader(image.width, image.height);
  pgm.append(reinterpret_cast<const char*>(image.pixels.data()),
             image.pixels.size());
  return WriteFileAtomically(pgm_path, pgm, error) &&
         WriteFileAtomically(yaml_path,
                             MapYaml(pgm_path, yaml_path, image.resolution,
                                     image.origin_x, image.origin_y, config),
                             error);
}

bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const OccupancyGrid& grid, std::string* error) {
  OccupancyGrid::Bounds b;
  if (!grid.ObservedBounds(&b)) {
    *error = pgm_path + ": empty map (no scan observed any cell)";
    return false;
  }
  const int64_t width = b.x1 - b.x0 + 1, height = b.y1 - b.y0 + 1;
  std::string pgm = PgmHeader(width, height);
  const size_t header = pgm.size();
  pgm.resize(header + static_cast<size_t>(width * height));
  grid.Render(b, 1, width, height, reinterpret_cast<uint8_t*>(&pgm[header]));
  const double res = grid.config().resolution;
  return WriteFileAtomically(pgm_path, pgm, error) &&
         WriteFileAtomically(
             yaml_path,
             MapYaml(pgm_path, yaml_path, res, static_cast<double>(b.x0) * res,
                     static_cast<double>(b.y0) * res, grid.config()),
             error);
}

bool ReadPgm(const std::string& path, MapImage* image, std::string* error) {
  std::string data;
  if (!text::ReadWholeFile(path, &data, error)) return false;
  size_t pos = 0;
  // Next header number, skipping white space and '#' comments.
  const auto next_number = [&](int64_t* value) {
    while (pos < data.size()) {
      if (data[pos] == '#') {
        while (pos < data.size() && data[pos] != '\n') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(data[pos]))) {
        ++pos;
      } else {
        break;
      }
    }
    const size_t start = pos;
    while (pos < data.size() &&
           std::isdigit(static_cast<unsigned char>(data[pos]))) {
      ++pos;
    }
    return pos > start && pos - start < 10 &&
           text::ParseInt64(std::string_view(data).substr(start, pos - start),
                            value);
  };
  int64_t width = 0, height = 0, maxval = 0;
  if (data.compare(0, 2, "P5") != 0) {
    *error = path + ": not a binary PGM (no P5 magic)";
    return false;
  }
  pos = 2;
  if (!next_number(&width) || !next_number(&height) || !next_number(&maxval) ||
      width <= 0 || height <= 0 || maxval <= 0 || maxval > 255 ||
      pos >= data.size() ||
      !std::isspace(static_cast<unsigned char>(data[pos]))) {
    *error = path + ": bad PGM header (expected P5 width height maxval<=255)";
    return false;
  }
  ++pos;  // The single white space before the pixels.
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (data.size() - pos < count) {
    *error = path + ": truncated PGM: " + std::to_string(data.size() - pos) +
             " pixel bytes for " + std::to_string(width) + " x " +
             std::to_string(height);
    return false;
  }
  image->width = static_cast<int>(width);
  image->height = static_cast<int>(height);
  image->pixels.assign(data.begin() + pos, data.begin() + pos + count);
  return true;
}

}  // namespace slam
