// The commands of slam-visual that read images (see apps/main.cc): they link
// OpenCV's image libraries, which the lean `slam` binary must not load.
#ifndef SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_
#define SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_

#include <string>
#include <vector>

namespace slam {

// slam run: the pipeline named by the config's `run.pipeline` (laser, the
// default, runs RunRunCommand; stereo runs the stereo visual odometry).
int RunRunOrStereoCommand(const std::vector<std::string>& args);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_VISUAL_COMMANDS_H_
