// Reading a KITTI-odometry-style stereo sequence folder (the file layer
// only: names, calibration, stamps; decoding the images is the stereo
// frontend's job, frontends/stereo/stereo_images.h).
//
//   DIR/image_0/   left images (rectified), any format cv::imread reads
//   DIR/image_1/   right images, the same names as image_0
//   DIR/calib.txt  "P0: 12 numbers" and "P1: 12 numbers" (3x4 row-major
//                  projection matrices; other labelled lines such as P2, P3,
//                  Tr are ignored), or the same two lines without labels
//                  (P0 first), as both occur in published copies
//   DIR/times.txt  optional, one stamp in seconds per frame
//   DIR/poses.txt  optional ground truth, KITTI poses (read elsewhere)
//
// Image files are sorted numerically by the digits of their name (000010
// after 000009, 10.png after 9.png); files whose names hold no digits are
// sorted by name after them. Left and right must list the same names.
//
// Calibration: P0 = K [I | 0], P1 = K [I | -b e_x] (rectified pair; K shared,
// fx = P[0][0], fy = P[1][1], cx = P[0][2], cy = P[1][2]); the baseline is
// b = -P1[0][3] / P1[0][0] and must be > 0. Anything else (a skew, different
// intrinsics left and right, a non-zero P0 translation beyond 1e-6 fx, a
// vertical offset) is an error naming the line: the frontend assumes a
// rectified pair with the left camera as the pose.
//
// Stamps: times.txt when present (one per image, strictly increasing);
// otherwise frame k gets k * default_frame_period and has_times is false.
//
// KITTI raw layout (a 2011_09_26_drive_XXXX_sync folder; detected by
// DIR/image_00/data):
//   DIR/image_00/data/, DIR/image_01/data/   rectified left and right images
//   DIR/image_00/timestamps.txt              date-time stamps, one per image
//                                            ("2011-09-26 13:02:25.967790592",
//                                            read as UTC nanoseconds since
//                                            1970)
//   calib_cam_to_cam.txt                     in DIR or in the date folder
//                                            above it: "P_rect_00:" and
//                                            "P_rect_01:" are P0 and P1
// The unrectified "extract" download (folder name ending in _extract, or
// images of the raw sensor size S_00 rather than S_rect_00) is refused.
#ifndef SLAM_DATASETS_KITTI_SEQUENCE_IO_H_
#define SLAM_DATASETS_KITTI_SEQUENCE_IO_H_

#include <string>
#include <string_view>
#include <vector>

#include "core/conventions.h"
#include "factors/camera_models.h"

namespace slam {

struct KittiSequence {
  std::string dir;
  std::vector<std::string> left_images;   // Full paths, in frame order.
  std::vector<std::string> right_images;  // Same names under image_1.
  std::vector<TimeNs> stamps;             // One per frame.
  bool has_times = false;                 // Stamps from a file.
  bool raw_layout = false;                // KITTI raw (image_00/data).
  StereoCalibration calibration;
  std::string calibration_path;
  std::string ground_truth_path;  // DIR/poses.txt when it exists, else "".
};

struct KittiSequenceOptions {
  double default_frame_period = 0.1;  // s, without times.txt (KITTI: 10 Hz).
  std::string calibration_path;       // Overrides DIR/calib.txt.
  std::string times_path;             // Overrides DIR/times.txt.
};

// False with "PATH[:LINE]: problem" on any problem listed above (a missing
// folder or file, no images, left/right counts or names that differ, a bad
// calibration line, a times.txt of the wrong length or order).
bool ReadKittiSequence(const std::string& dir,
                       const KittiSequenceOptions& options,
                       KittiSequence* sequence, std::string* error);

// One KITTI raw date-time stamp "YYYY-MM-DD HH:MM:SS[.fraction]" (at most
// 9 fraction digits) as nanoseconds since 1970-01-01 00:00:00 UTC; false if
// malformed or out of range.
bool ParseKittiRawTimestamp(std::string_view text, TimeNs* stamp);

// Parses calib.txt alone (the rules above).
bool ReadKittiStereoCalibration(const std::string& path,
                                StereoCalibration* calibration,
                                std::string* error);

// Image file names of a folder in frame order (the sorting rule above);
// false if the folder cannot be listed.
bool ListImageFiles(const std::string& dir, std::vector<std::string>* paths,
                    std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_KITTI_SEQUENCE_IO_H_
