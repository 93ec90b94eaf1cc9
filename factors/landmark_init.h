// Initial values of landmark (point) nodes from their observations, for
// graphs read without landmark values (iSAM, stereo VO, TORO BR). Run it
// after the poses are initialized (core/initialization.h): each point is set
// from its observations, in FactorId order:
//   kRangeBearing2   the first one, inverted (core/triangulation.h);
//   kRelativePoint2  the first one, X z;
//   kRelativePoint3  the first one, (X S) z;
//   kStereo          the first one with positive disparity, triangulated;
//   kReprojection    the midpoint of the two rays (undistorted) with the
//                    widest angle between the first ray and a later one; a
//                    point with a single usable ray is put on it at unit
//                    depth and counted as weak.
// A point no factor of these kinds observes is left as it is.
#ifndef SLAM_FACTORS_LANDMARK_INIT_H_
#define SLAM_FACTORS_LANDMARK_INIT_H_

#include <set>

#include "core/graph.h"

namespace slam {

struct LandmarkInitReport {
  int initialized = 0;  // Points set from their observations.
  int weak = 0;         // Of those, monocular points with one usable ray.
  int failed = 0;       // Observed points no observation could place.
};

// Initializes the point nodes in `only` (all kPoint2/kPoint3 nodes if null).
LandmarkInitReport InitializeLandmarks(Graph* graph,
                                       const std::set<Key>* only = nullptr);

}  // namespace slam

#endif  // SLAM_FACTORS_LANDMARK_INIT_H_
