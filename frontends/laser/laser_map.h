// The occupancy-grid map of a laser SLAM run (occupancy_grid.h) and a measure
// of its sharpness.
#ifndef SLAM_FRONTENDS_LASER_LASER_MAP_H_
#define SLAM_FRONTENDS_LASER_LASER_MAP_H_

#include <vector>

#include "core/sensors/laser_data.h"
#include "frontends/laser/laser_slam.h"
#include "frontends/laser/occupancy_grid.h"

namespace slam {

// Inserts every keyframe's scan at the keyframe's current (optimized) pose.
// `scans` are the scans given to slam.AddScan, in the same order.
void InsertKeyframeScans(const LaserSlam& slam,
                         const std::vector<LaserScan>& scans,
                         OccupancyGrid* grid);

// Sharpness. Cell states as map_server thresholds them (a cell passed
// through once is still "undecided"), and the cells with mixed evidence:
// log-odds strictly between one free update (l_free) and one hit (l_occ),
// which only a cell both hit and passed through can have. Misaligned scans
// blur walls into bands of mixed cells; MixedFraction = mixed / (mixed +
// occupied) is small for a sharp map.
struct MapSharpness {
  size_t observed = 0;
  size_t occupied = 0;
  size_t free = 0;
  size_t undecided = 0;
  size_t mixed = 0;
  double MixedFraction() const {
    return mixed + occupied > 0
               ? static_cast<double>(mixed) / (mixed + occupied)
               : 0.0;
  }
};
MapSharpness MeasureSharpness(const OccupancyGrid& grid);

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_LASER_MAP_H_
