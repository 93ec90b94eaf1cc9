// Messages on stderr quote input (tokens, keys, values, paths): a control
// byte or an ANSI escape sequence from a file must not reach the terminal.
#ifndef SLAM_APPS_SAFE_STDERR_H_
#define SLAM_APPS_SAFE_STDERR_H_

namespace slam {

// From now on, std::cerr writes control bytes other than '\n' and '\t'
// (ESC, '\r', BEL, ...) as '?'. Called once at the start of main(); the
// progress bars, which redraw with '\r' on purpose, write through stdio.
void FilterControlBytesOnStderr();

}  // namespace slam

#endif  // SLAM_APPS_SAFE_STDERR_H_
