#include "frontends/laser/laser_map.h"

namespace slam {

void InsertKeyframeScans(const LaserSlam& slam,
                         const std::vector<LaserScan>& scans,
                         OccupancyGrid* grid) {
  const auto& records = slam.scan_records();
  int last_keyframe = -1;
  for (size_t i = 0; i < records.size() && i < scans.size(); ++i) {
    if (records[i].keyframe == last_keyframe) continue;
    last_keyframe = records[i].keyframe;
    grid->InsertScan(slam.KeyframePose(last_keyframe) * scans[i].laser_offset,
                     scans[i]);
  }
}

MapSharpness MeasureSharpness(const OccupancyGrid& grid) {
  MapSharpness s;
  const MapImage image = grid.ToImage();
  const double res = image.resolution;
  // Strictly between one free update and one hit: only reachable with both.
  const double l_free = grid.config().l_free + 1e-6;
  const double l_occ = grid.config().l_occ - 1e-6;
  for (int r = 0; r < image.height; ++r) {
    // Cell centres; image row 0 is the largest y.
    const double y = image.origin_y + (image.height - 1 - r + 0.5) * res;
    for (int c = 0; c < image.width; ++c) {
      const double x = image.origin_x + (c + 0.5) * res;
      if (!grid.Observed(x, y)) continue;
      ++s.observed;
      const double l = grid.LogOdds(x, y);
      if (l > l_free && l < l_occ) ++s.mixed;
      switch (grid.State(x, y)) {
        case CellState::kOccupied:
          ++s.occupied;
          break;
        case CellState::kFree:
          ++s.free;
          break;
        case CellState::kUnknown:
          ++s.undecided;
          break;
      }
    }
  }
  return s;
}

}  // namespace slam
