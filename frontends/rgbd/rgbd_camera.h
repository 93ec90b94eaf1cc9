// The camera of an RGB-D frame source: pinhole intrinsics with OpenCV's
// 5-parameter distortion, and the presets of the TUM RGB-D benchmark's
// Kinects.
//
// Presets (the dataset's published calibration of the Kinects,
// 640 x 480; distortion k1 k2 p1 p2 k3 in OpenCV's model):
//   freiburg1  fx 517.3 fy 516.5 cx 318.6 cy 255.3,
//              0.2624 -0.9531 -0.0054 0.0026 1.1633
//   freiburg2  fx 520.9 fy 521.0 cx 325.1 cy 249.7,
//              0.2312 -0.7849 -0.0033 -0.0001 0.9172
//   freiburg3  fx 535.4 fy 539.2 cx 320.1 cy 247.6, no distortion
// The preset may be guessed from the folder name, only when the name says
// freiburg1, freiburg2 or freiburg3 (or fr1/fr2/fr3 as a word).
#ifndef SLAM_FRONTENDS_RGBD_RGBD_CAMERA_H_
#define SLAM_FRONTENDS_RGBD_RGBD_CAMERA_H_

#include <string>

namespace slam {

// Pinhole intrinsics with OpenCV's 5-parameter distortion.
struct RgbdCamera {
  std::string name;  // The preset, or "custom".
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  bool HasDistortion() const {
    return k1 != 0.0 || k2 != 0.0 || p1 != 0.0 || p2 != 0.0 || k3 != 0.0;
  }
};

// The preset `name` (freiburg1, freiburg2, freiburg3); false if unknown.
bool TumCameraPreset(const std::string& name, RgbdCamera* camera);
// The preset a folder name says ("" when it names none or several).
std::string GuessTumCameraPreset(const std::string& folder);

}  // namespace slam

#endif  // SLAM_FRONTENDS_RGBD_RGBD_CAMERA_H_
