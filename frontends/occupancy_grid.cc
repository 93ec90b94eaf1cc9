#include "frontends/occupancy_grid.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"

namespace slam {
namespace {

// Cells added beyond what a scan needs when the grid grows (at least).
constexpr int64_t kGrowMargin = 64;

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
  const double side = 2.0 * c.max_usable_range / c.resolution + 1.0;
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

int64_t OccupancyGrid::Offset(int64_t ix, int64_t iy) const {
  const int64_t col = ix - min_ix_;
  const int64_t row = iy - min_iy_;
  if (col < 0 || row < 0 || col >= width_ || row >= height_) return -1;
  return row * width_ + col;
}

bool OccupancyGrid::Grow(int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
  if (width_ > 0 && x0 >= min_ix_ && y0 >= min_iy_ && x1 < min_ix_ + width_ &&
      y1 < min_iy_ + height_) {
    return true;
  }
  int64_t nx0 = x0 - kGrowMargin;
  int64_t ny0 = y0 - kGrowMargin;
  int64_t nx1 = x1 + kGrowMargin;
  int64_t ny1 = y1 + kGrowMargin;
  if (width_ > 0) {
    // Grow by at least half the current size on a side that must grow, so
    // that a long run costs few copies.
    const int64_t mx = std::max(kGrowMargin, width_ / 2);
    const int64_t my = std::max(kGrowMargin, height_ / 2);
    nx0 = x0 < min_ix_ ? std::min(nx0, min_ix_ - mx) : min_ix_;
    ny0 = y0 < min_iy_ ? std::min(ny0, min_iy_ - my) : min_iy_;
    const int64_t old_x1 = min_ix_ + width_ - 1;
    const int64_t old_y1 = min_iy_ + height_ - 1;
    nx1 = x1 > old_x1 ? std::max(nx1, old_x1 + mx) : old_x1;
    ny1 = y1 > old_y1 ? std::max(ny1, old_y1 + my) : old_y1;
  }
  const auto too_large = [&] {
    return static_cast<double>(nx1 - nx0 + 1) *
               static_cast<double>(ny1 - ny0 + 1) >
           static_cast<double>(config_.max_cells);
  };
  if (too_large()) {
    // Without the margins, in case that fits.
    nx0 = width_ > 0 ? std::min(x0, min_ix_) : x0;
    ny0 = width_ > 0 ? std::min(y0, min_iy_) : y0;
    nx1 = width_ > 0 ? std::max(x1, min_ix_ + width_ - 1) : x1;
    ny1 = width_ > 0 ? std::max(y1, min_iy_ + height_ - 1) : y1;
    if (too_large()) return false;
  }
  const int64_t new_width = nx1 - nx0 + 1;
  const int64_t new_height = ny1 - ny0 + 1;
  std::vector<float> log_odds(new_width * new_height, 0.0f);
  std::vector<uint32_t> last_scan(new_width * new_height, 0);
  for (int64_t row = 0; row < height_; ++row) {
    const int64_t to = (row + min_iy_ - ny0) * new_width + (min_ix_ - nx0);
    std::copy_n(log_odds_.begin() + row * width_, width_,
                log_odds.begin() + to);
    std::copy_n(last_scan_.begin() + row * width_, width_,
                last_scan.begin() + to);
  }
  log_odds_.swap(log_odds);
  last_scan_.swap(last_scan);
  min_ix_ = nx0;
  min_iy_ = ny0;
  width_ = new_width;
  height_ = new_height;
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
  if (!beams.empty() && !Grow(x0, y0, x1, y1)) return false;
  ++scans_inserted_;
  if (beams.empty()) return true;
  const uint32_t stamp = ++scan_counter_;
  const auto update = [&](int64_t ix, int64_t iy, double delta) {
    const int64_t o = Offset(ix, iy);
    if (last_scan_[o] == stamp) return;  // Once per scan; hits first.
    last_scan_[o] = stamp;
    log_odds_[o] =
        static_cast<float>(std::clamp(static_cast<double>(log_odds_[o]) + delta,
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
  const int64_t o = Offset(CellIndex(x), CellIndex(y));
  return o < 0 ? 0.0 : log_odds_[o];
}

bool OccupancyGrid::Observed(double x, double y) const {
  const int64_t o = Offset(CellIndex(x), CellIndex(y));
  return o >= 0 && last_scan_[o] != 0;
}

CellState OccupancyGrid::StateOf(int64_t offset) const {
  if (offset < 0 || last_scan_[offset] == 0) return CellState::kUnknown;
  const double p = Probability(log_odds_[offset]);
  if (p > config_.occupied_thresh) return CellState::kOccupied;
  if (p < config_.free_thresh) return CellState::kFree;
  return CellState::kUnknown;
}

CellState OccupancyGrid::State(double x, double y) const {
  return StateOf(Offset(CellIndex(x), CellIndex(y)));
}

MapImage OccupancyGrid::ToImage() const {
  MapImage image;
  image.resolution = config_.resolution;
  int64_t c0 = width_, r0 = height_, c1 = -1, r1 = -1;
  for (int64_t row = 0; row < height_; ++row) {
    for (int64_t col = 0; col < width_; ++col) {
      if (last_scan_[row * width_ + col] == 0) continue;
      c0 = std::min(c0, col);
      c1 = std::max(c1, col);
      r0 = std::min(r0, row);
      r1 = std::max(r1, row);
    }
  }
  if (c1 < 0) return image;
  image.width = static_cast<int>(c1 - c0 + 1);
  image.height = static_cast<int>(r1 - r0 + 1);
  image.origin_x = static_cast<double>(min_ix_ + c0) * config_.resolution;
  image.origin_y = static_cast<double>(min_iy_ + r0) * config_.resolution;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height);
  for (int r = 0; r < image.height; ++r) {
    const int64_t row = r1 - r;  // Image row 0 is the largest y.
    for (int c = 0; c < image.width; ++c) {
      const CellState state = StateOf(row * width_ + c0 + c);
      image.pixels[static_cast<size_t>(r) * image.width + c] =
          state == CellState::kOccupied ? kPixelOccupied
          : state == CellState::kFree   ? kPixelFree
                                        : kPixelUnknown;
    }
  }
  return image;
}

bool WriteMapPgmYaml(const std::string& pgm_path, const std::string& yaml_path,
                     const MapImage& image, const OccupancyGridConfig& config,
                     std::string* error) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height) {
    *error = pgm_path + ": empty map (no scan observed any cell)";
    return false;
  }
  std::string pgm = "P5\n" + std::to_string(image.width) + " " +
                    std::to_string(image.height) + "\n255\n";
  pgm.append(reinterpret_cast<const char*>(image.pixels.data()),
             image.pixels.size());
  namespace fs = std::filesystem;
  const fs::path pgm_file(pgm_path);
  const fs::path yaml_file(yaml_path);
  const std::string image_name = fs::absolute(pgm_file).parent_path() ==
                                         fs::absolute(yaml_file).parent_path()
                                     ? pgm_file.filename().string()
                                     : fs::absolute(pgm_file).string();
  std::string yaml = "image: " + image_name + "\nresolution: ";
  text::AppendDouble(image.resolution, &yaml);
  yaml += "\norigin: [";
  text::AppendDouble(image.origin_x, &yaml);
  yaml += ", ";
  text::AppendDouble(image.origin_y, &yaml);
  yaml += ", 0.0]\nnegate: 0\noccupied_thresh: ";
  text::AppendDouble(config.occupied_thresh, &yaml);
  yaml += "\nfree_thresh: ";
  text::AppendDouble(config.free_thresh, &yaml);
  yaml += "\n";
  return WriteFileAtomically(pgm_path, pgm, error) &&
         WriteFileAtomically(yaml_path, yaml, error);
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
