// Reading a TUM RGB-D recording folder as downloaded (the file layer only:
// lists and association; decoding the images is the RGB-D frontend's job,
// frontends/rgbd/rgbd_source.h):
//
//   DIR/rgb.txt          "# comment" lines, then "timestamp path" per colour
//                        image (path relative to DIR, e.g.
//                        rgb/1305031229.5.png)
//   DIR/depth.txt        the same for the depth images (16-bit PNG)
//   DIR/groundtruth.txt  optional, "timestamp tx ty tz qx qy qz qw"
//                        (camera pose in the motion-capture frame)
//   DIR/accelerometer.txt  ignored
//
// Stamps must not go backwards within a list (an error naming the line);
// two colour images with the same stamp are an error too (two frames at one
// time), two depth images with the same stamp are allowed (the association
// takes one, the other is reported unmatched).
//
// Association (TUM's associate.py): every pair of a colour and a depth stamp
// closer than max_difference seconds is a candidate; candidates are taken
// in order of increasing difference, each stamp at most once; the frames are
// the colour images that got a depth image, in colour order. Colour and
// depth images left without a partner are listed (unmatched_rgb,
// unmatched_depth) for the caller to report; none matched at all is an
// error.
//
// The cameras (the Freiburg presets): frontends/rgbd/rgbd_camera.h.
#ifndef SLAM_DATASETS_TUM_RGBD_IO_H_
#define SLAM_DATASETS_TUM_RGBD_IO_H_

#include <string>
#include <utility>
#include <vector>

#include "core/conventions.h"

namespace slam {

// One line of rgb.txt or depth.txt.
struct TumImageEntry {
  TimeNs stamp = 0;
  double seconds = 0.0;  // As written (the association works on these).
  std::string path;      // Full path (DIR joined with the listed path).
  int64_t line = 0;
};

// Parses a list file; false with "PATH:LINE: problem" (a line without two
// fields, a bad number, a stamp before the previous one, or an equal one
// unless allow_equal_stamps) or when the file holds no entry.
bool ReadTumImageList(const std::string& path, const std::string& dir,
                      bool allow_equal_stamps,
                      std::vector<TumImageEntry>* entries, std::string* error);

// associate.py's matching of stamps `a` to stamps `b` (seconds): pairs
// (index in a, index in b), sorted by a.
std::vector<std::pair<size_t, size_t>> AssociateStamps(
    const std::vector<double>& a, const std::vector<double>& b,
    double max_difference);

struct TumRgbdFrame {
  TumImageEntry rgb;
  TumImageEntry depth;
};

struct TumRgbdSequence {
  std::string dir;
  std::string rgb_list, depth_list;  // The list files read.
  std::vector<TumRgbdFrame> frames;  // Colour order.
  std::vector<TumImageEntry> unmatched_rgb, unmatched_depth;
  std::string ground_truth_path;  // DIR/groundtruth.txt if present, else "".
};

struct TumRgbdOptions {
  double max_difference = 0.02;  // s, associate.py's default.
};

bool ReadTumRgbdSequence(const std::string& dir, const TumRgbdOptions& options,
                         TumRgbdSequence* sequence, std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_TUM_RGBD_IO_H_
