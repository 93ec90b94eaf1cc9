// Writing output files so that a failure never leaves a partial or corrupted
// file behind: the content goes to a temporary file beside the target, which
// is renamed over the target only once everything was written and flushed.
#ifndef SLAM_DATASETS_ATOMIC_FILE_H_
#define SLAM_DATASETS_ATOMIC_FILE_H_

#include <string>

namespace slam {

// Writes `content` to `path` atomically. On failure returns false, sets
// *error to "PATH: problem" and leaves no file (neither target nor temporary).
bool WriteFileAtomically(const std::string& path, const std::string& content,
                         std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_ATOMIC_FILE_H_
