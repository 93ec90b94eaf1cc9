// Reading the stereo visual-odometry files of GTSAM's StereoVOExample_large
// (KITTI-derived; /work/shared/datasets/stereo_vo_factors/):
//
//   calibration   one line "fx fy skew cx cy baseline" (skew must be 0:
//                 the rectified stereo model has none);
//   camera poses  "id m00 m01 .. m33": the 4x4 homogeneous matrix, row-major,
//                 of T_world_camera (camera-to-world; camera frame x right,
//                 y down, z forward; checked: reprojecting the points with it
//                 gives residuals of a fraction of a pixel, its inverse
//                 hundreds of pixels);
//   factors       "pose_id landmark_id uL uR v X Y Z": a rectified stereo
//                 measurement of the landmark from the pose, and (X, Y, Z) the
//                 landmark in that camera's frame (GTSAM uses it, through
//                 pose.transformFrom, as the landmark's initial value).
//
// The graph gets Pose3Key(id) camera nodes with the file's poses (rotation
// blocks projected to the nearest rotation), Point3Key(landmark_id +
// kStereoVoLandmarkIdOffset) point nodes initialized from their first
// observation's (X, Y, Z), and one stereo factor per measurement
// (factors/stereo_projection.h) with unit information (1 pixel, as GTSAM's
// example). The landmark ids are offset so that they stay distinct from the
// pose ids also for tools that read one id space for both. Bad input:
// "PATH:LINE: problem" (field counts, numbers, unknown or duplicate pose
// ids, a skew or a non-positive focal length or baseline). A non-positive
// disparity is not an error: such points get their initial value from
// (X, Y, Z) all the same.
#ifndef SLAM_DATASETS_STEREO_VO_IO_H_
#define SLAM_DATASETS_STEREO_VO_IO_H_

#include <cstdint>
#include <string>

#include "core/graph.h"
#include "factors/camera_models.h"

namespace slam {

constexpr int64_t kStereoVoLandmarkIdOffset = 1000000;

struct StereoVoReport {
  int poses = 0;
  int landmarks = 0;
  int measurements = 0;
  StereoCalibration calibration;
};

bool ReadStereoVo(const std::string& factors_path,
                  const std::string& calibration_path,
                  const std::string& poses_path, Graph* graph,
                  StereoVoReport* report, std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_STEREO_VO_IO_H_
