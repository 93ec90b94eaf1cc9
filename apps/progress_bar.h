// A progress bar on stderr for long work (log processing).
#ifndef SLAM_APPS_PROGRESS_BAR_H_
#define SLAM_APPS_PROGRESS_BAR_H_

#include <unistd.h>

#include <cstdio>
#include <string>

namespace slam {

// A progress bar on stderr: one line redrawn when the percentage changes on
// a terminal; in a log file (stderr not a terminal) one line every 10 %, so
// that CI logs and redirected output stay readable.
class ProgressBar {
 public:
  explicit ProgressBar(const char* label)
      : label_(label), terminal_(isatty(fileno(stderr)) != 0) {}
  void Update(double fraction) {
    int percent = static_cast<int>(fraction * 100.0);
    if (!terminal_) percent -= percent % 10;
    if (percent <= last_) return;
    last_ = percent;
    const int filled = percent / 4;
    std::fprintf(stderr, "%s%-12s [%s%s] %3d%%", terminal_ ? "\r" : "", label_,
                 std::string(filled, '#').c_str(),
                 std::string(25 - filled, '.').c_str(), percent);
    if (!terminal_ || percent >= 100) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  void Done() { Update(1.0); }

 private:
  const char* label_;
  bool terminal_;
  int last_ = -1;
};

}  // namespace slam

#endif  // SLAM_APPS_PROGRESS_BAR_H_
