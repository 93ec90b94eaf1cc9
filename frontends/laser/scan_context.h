// A rotation-invariant place descriptor of a 2D point cloud for global loop
// search, after Scan Context (Kim and Kim, "Scan Context: Egocentric
// Spatial Descriptor for Place Recognition within 3D Point Cloud Map", IROS
// 2018), reduced to 2D: the plane around the cloud's origin is cut into
// `rings` rings of equal width out to `max_range` and `sectors` sectors;
// a polar cell is 1 when a point falls into it, else 0.
//  - The ring key does not change when the cloud rotates about its origin:
//    per ring, the fraction of occupied cells and the magnitudes of the
//    first `key_harmonics` harmonics of the ring's sector occupancy (its
//    discrete Fourier transform over the sectors, divided by their count;
//    a rotation by whole sectors is a cyclic shift, which changes only the
//    phases). It preselects candidates by Euclidean distance over every
//    keyframe of the map. The occupied fraction alone tells little apart
//    indoors (every corridor has about the same one per ring); the
//    harmonics keep how the occupancy is spread round the ring (one wall,
//    two parallel walls, a corner, an opening).
//  - The descriptor distance is the mean over sectors of 1 - cosine of the
//    two sector columns (sectors empty in both count as equal), minimized
//    over the cyclic sector shifts; the best shift estimates the rotation
//    between the two clouds to one sector.
#ifndef SLAM_FRONTENDS_LASER_SCAN_CONTEXT_H_
#define SLAM_FRONTENDS_LASER_SCAN_CONTEXT_H_

#include <vector>

#include "frontends/laser/scan_matcher.h"

namespace slam {

struct ScanContextOptions {
  int rings = 20;
  int sectors = 60;
  double max_range = 20.0;  // m.
  int key_harmonics = 4;    // Ring-key harmonics per ring (0: occupancy only).
};

struct ScanContext {
  int rings = 0, sectors = 0;
  std::vector<float> cells;  // rings x sectors, row-major by ring.
  // Per ring: occupied fraction, then the harmonic magnitudes.
  std::vector<float> ring_key;
  bool empty() const { return cells.empty(); }
};

ScanContext MakeScanContext(const Points2& points,
                            const ScanContextOptions& options);

// Squared Euclidean distance of the ring keys.
double RingKeyDistance(const ScanContext& a, const ScanContext& b);

// Distance in [0, 1] (0: identical) at the best cyclic shift; writes the
// rotation (rad) that takes a's frame into b's (a point at bearing phi in
// a is at bearing phi + *rotation in b).
double ScanContextDistance(const ScanContext& a, const ScanContext& b,
                           double* rotation);

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_SCAN_CONTEXT_H_
