// A synthetic stereo world for the visual-odometry and loop-closure tests:
// 3D points with binary descriptors, seen by a rectified stereo rig along a
// known path, turned into feature frames (stereo_frame.h) directly, without
// images. Known answer: the camera poses and every keypoint's true point.
//
// World: points scattered in a band around the path (lateral offset
// |x| in [min_lateral, max_lateral] on either side, height in
// [min_height, max_height], y down as in the camera frame), spaced so that
// about points_per_metre fall along each metre of path. Path: frames
// step metres apart, the camera looking along the direction of travel; a
// straight line with a gentle weave, or a closed circle of the given
// radius (loop: true) travelled laps times, so that places are revisited.
// Each point has a random 256-bit descriptor; each observation flips
// descriptor_flips random bits of it (views differ a little).
// Keypoints: the projections of points in front of the camera (depth in
// [min_depth, max_depth]) inside the image, plus Gaussian pixel noise of
// pixel_sigma (u, v and the right image's u independently; or, with
// disparity_sigma >= 0, u and v, and the disparity with disparity_sigma: the
// right u then shares the left u's error, as with a disparity measured by
// patch alignment around the keypoint); the octave is 0. Stereo u_right
// is given when the disparity is at least 1 pixel.
// Disparity errors as a stereo matcher makes them (after the pixel noise):
// a systematic disparity_bias (pixels added to every disparity: a sub-pixel
// interpolation bias, or a small offset between the rectified images) and a
// quantization of the disparity to multiples of disparity_quantum pixels
// (0: none), both applied through u_right.
// Outliers: for a fraction of the keypoints a spurious keypoint with the
// same descriptor appears at a random place of the image with a random
// disparity (a wrong association by appearance; its true point is -1), and
// a fraction of the keypoints get a right u off by stereo_outlier_pixels (a
// wrong stereo match).
#ifndef SLAM_FRONTENDS_STEREO_STEREO_SIMULATOR_H_
#define SLAM_FRONTENDS_STEREO_STEREO_SIMULATOR_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/trajectory.h"
#include "frontends/stereo/stereo_frame.h"

namespace slam {

struct StereoSimulationConfig {
  StereoCalibration calibration{500.0, 500.0, 320.0, 240.0, 0.5};
  int width = 640;
  int height = 480;
  int frames = 40;
  double step = 1.0;  // Metres between frames.
  bool loop = false;
  double loop_radius = 20.0;
  double laps = 1.0;             // Loop only: times round the circle.
  double weave_amplitude = 0.5;  // Straight path only: lateral weave (m).
  // Speed: frame f is at arc length step * (f + speed_variation *
  // speed_period / (2 pi) * sin(2 pi f / speed_period)), i.e. the distance
  // per frame varies as step * (1 + speed_variation * cos(2 pi f /
  // speed_period)) (stop and go; frames are 0.1 s apart, so the largest
  // acceleration is step * speed_variation * 2 pi / speed_period / 0.01
  // m/s^2). 0: constant speed.
  double speed_variation = 0.0;
  double speed_period = 20.0;  // Frames.
  double points_per_metre = 40.0;
  double min_lateral = 2.0, max_lateral = 15.0;
  double min_height = -4.0, max_height = 2.0;
  double min_depth = 1.0, max_depth = 60.0;
  double pixel_sigma = 0.0;
  double disparity_sigma = -1.0;   // Pixels; < 0: see above.
  double disparity_bias = 0.0;     // Pixels.
  double disparity_quantum = 0.0;  // Pixels; 0: not quantized.
  int descriptor_flips = 4;
  double outlier_fraction = 0.0;         // Spurious keypoints.
  double stereo_outlier_fraction = 0.0;  // Wrong right u.
  double stereo_outlier_pixels = 8.0;
  uint32_t seed = 1;
};

struct StereoSimulation {
  Trajectory poses;  // T_world_camera per frame; frame 0 at the origin.
  std::vector<Eigen::Vector3d> points;
  std::vector<StereoFeatureFrame> frames;
  // Per frame, per keypoint: the index of the point it shows (-1: a
  // spurious keypoint), and whether it is an outlier (spurious or with a
  // wrong right u).
  std::vector<std::vector<int>> true_point;
  std::vector<std::vector<bool>> outlier;
};

StereoSimulation SimulateStereo(const StereoSimulationConfig& config);

}  // namespace slam

#endif  // SLAM_FRONTENDS_STEREO_STEREO_SIMULATOR_H_
