// Capture instants of a fixed-rate camera whose frames are stamped on
// arrival. A Kinect 1 / Xtion (TUM RGB-D) captures colour frames on its own
// 30 Hz clock, but the driver stamps each frame when it reaches the PC: on
// TUM fr1/rpy the stamp intervals are 27.2 .. 40.2 ms in a repeating
// pattern while a line through them has a period of 33.301 ms and leaves
// residuals of 2.3 ms rms (4.8 ms at most). The poses the images give are
// those of the capture instants; labelled with the stamps they are off by
// the angular rate times the jitter (at 90 deg/s and 4 ms: 0.36 deg), which
// is what the per-frame rotation error of that recording was made of.
//
// FitCaptureClock recovers the capture instants from the stamps: frame
// counts from the stamp intervals over their median (a dropped frame counts
// two), a least-squares line stamp = a + period * count, then shifted to the
// lower envelope of the stamps (a frame never arrives before it was
// captured; the constant part of the latency is not observable from the
// stamps and is left out). PosesAtStamps then moves a trajectory estimated
// at the capture instants to the stamps, interpolating between the two
// neighbouring captures (linear in position, slerp in rotation) and
// extrapolating the first or last interval's motion at the ends.
//
// Limits: a frame that arrives more than half a period late reads as a
// dropped frame and shifts the counts after it; the residuals then exceed
// a quarter period and the fit is refused (the stamps are used as they
// are, as before). The line assumes the sensor's clock keeps a constant
// rate against the PC's over the run.
#ifndef SLAM_FRONTENDS_VISUAL_CAPTURE_CLOCK_H_
#define SLAM_FRONTENDS_VISUAL_CAPTURE_CLOCK_H_

#include <vector>

#include "core/conventions.h"
#include "core/trajectory.h"

namespace slam {

struct CaptureClock {
  // The stamps fit a fixed rate: at least 3 strictly increasing stamps whose
  // residuals from the line stay below a quarter of its period. Otherwise
  // capture holds the stamps themselves.
  bool fixed_rate = false;
  double period = 0.0;          // s.
  double jitter_rms = 0.0;      // s, the stamps' residuals from the line.
  double latency_max = 0.0;     // s, largest stamp - capture.
  std::vector<TimeNs> capture;  // One per stamp.
};

CaptureClock FitCaptureClock(const std::vector<TimeNs>& stamps);

// The poses of `at_capture` (pose i taken at capture[i], increasing) at
// their own stamps; `at_capture` unchanged if the sizes differ or it has
// fewer than two poses.
Trajectory PosesAtStamps(const Trajectory& at_capture,
                         const std::vector<TimeNs>& capture);

}  // namespace slam

#endif  // SLAM_FRONTENDS_VISUAL_CAPTURE_CLOCK_H_
