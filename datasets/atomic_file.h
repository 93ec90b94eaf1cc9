// Writing output files so that a failure never leaves a partial or corrupted
// file behind: the content goes to a temporary file beside the target
// (PATH.tmp.XXXXXX) and is renamed over the target only once everything was
// written and closed without error, so readers see the old file or the
// complete new one. There is no fsync: it cost up to 20 ms per output in
// the benchmarks, and ext4 (data=ordered, auto_da_alloc) already flushes
// the data of a file renamed over another. The new file keeps the mode of
// the file it replaces (or 0644).
#ifndef SLAM_DATASETS_ATOMIC_FILE_H_
#define SLAM_DATASETS_ATOMIC_FILE_H_

#include <string>
#include <string_view>

namespace slam {

// Writes `contents` to `path` atomically. On failure returns false, sets
// *error to "PATH: problem" and leaves PATH untouched and no temporary file.
bool WriteFileAtomically(const std::string& path, std::string_view contents,
                         std::string* error);

}  // namespace slam

#endif  // SLAM_DATASETS_ATOMIC_FILE_H_
