// The commands of slam-visual that read images (see apps/main.cc): they link
// OpenCV's image libraries, which the lean `slam` binary must not load.
#ifndef SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_
#define SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_

#include <string>
#include <vector>

namespace slam {

// slam run: the pipeline named by the config's `run.pipeline` (laser, the
// default, runs RunRunCommand; stereo runs the visual SLAM pipeline on a
// stereo sequence, rgbd RunRgbdCommand).
int RunRunOrStereoCommand(const std::vector<std::string>& args);
// slam run with run.pipeline: rgbd (visual SLAM on a TUM RGB-D folder).
int RunRgbdCommand(const std::vector<std::string>& args);

// slam vocabulary: trains a bag-of-words vocabulary of ORB descriptors on
// image folders (or converts a DBoW2 YAML one) into the binary format.
int RunVocabularyCommand(const std::vector<std::string>& args);

// slam loops: visual loop detection over an image sequence, scored against a
// ground-truth loop matrix.
int RunLoopsCommand(const std::vector<std::string>& args);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_
