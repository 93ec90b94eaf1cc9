#include "apps/commands.h"
#include "apps/visual/visual_commands.h"

namespace slam {

int RunRunOrStereoCommand(const std::vector<std::string>& args) {
  return RunRunCommand(args);
}

}  // namespace slam
