// The subcommands of the `slam` binary. Each runs after gflags has parsed the
// command line; `args` holds the positional arguments after the subcommand.
// Each returns the process exit code (0 on success) and reports errors on
// stderr naming the file, line and problem.
#ifndef SLAM_APPS_COMMANDS_H_
#define SLAM_APPS_COMMANDS_H_

#include <string>
#include <vector>

namespace slam {

int RunOptimizeCommand(const std::vector<std::string>& args);
int RunInfoCommand(const std::vector<std::string>& args);
int RunSimulateCommand(const std::vector<std::string>& args);
int RunEvalCommand(const std::vector<std::string>& args);
int RunRunCommand(const std::vector<std::string>& args);
int RunInertialCommand(const std::vector<std::string>& args);

}  // namespace slam

#endif  // SLAM_APPS_COMMANDS_H_
