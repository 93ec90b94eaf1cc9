// Handing the image commands from `slam` to `slam-visual` (see apps/main.cc
// and apps/CMakeLists.txt for why there are two binaries).
//
// slam-visual is looked up, in order: $SLAM_VISUAL_BINARY, beside the running
// executable, and at the path where the build put it.
#ifndef SLAM_APPS_VISUAL_FORWARD_H_
#define SLAM_APPS_VISUAL_FORWARD_H_

#include <string>
#include <vector>

namespace slam {

// Commands that slam-visual runs: `run` (laser or stereo, chosen by the
// config), and the place-recognition commands.
bool IsVisualCommand(const std::string& name);

// Replaces the process by slam-visual with the same arguments; returns only
// on failure (1, with a message naming the paths tried).
int ForwardToVisualBinary(int argc, char** argv);

// The table entry of a forwarded command in `slam` (never called there;
// returns 1 with a message if it is).
int RunForwardedCommand(const std::vector<std::string>& args);

}  // namespace slam

#endif  // SLAM_APPS_VISUAL_FORWARD_H_
