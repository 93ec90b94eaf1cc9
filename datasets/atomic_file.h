// Writing output files so that a failure never leaves a partial or corrupted
// file behind.
//
// A regular file (or a path that does not exist yet) is written to a
// temporary file beside it, flushed to disk (fsync) and renamed over the
// target only once everything was written and closed without error, so
// readers see the old file or the complete new one. The new file keeps the
// mode of the file it replaces (or 0644). A symbolic link is followed: its
// final target is replaced, the link stays. Anything else that exists
// (/dev/null, a FIFO, a device) is never replaced: it is opened and written
// directly. A directory is an error.
//
// Temporary files are named PATH.slam-tmp-PID-XXXXXX, so that a leftover is
// recognisable. SIGINT, SIGTERM, SIGHUP and SIGQUIT remove the temporaries of
// the process before it dies as the signal wants; a leftover of a process
// that was killed (SIGKILL) is removed by the next write of the same PATH
// once that process is gone.
//
// Output folders: CreateOutputFolder creates a folder and its missing
// parents; those it created are removed again (when empty) if the current
// OutputStage is discarded or on one of the signals above, so a failed or
// interrupted command leaves no empty folder behind.
//
// OutputStage: a command that writes several outputs keeps them all
// unpublished (written, as temporaries) until it has succeeded: while a stage
// is active on the thread, WriteFileAtomically defers its renames to
// OutputStage::Commit, and a stage destroyed without Commit removes its
// temporaries. So a command that fails after writing some of its outputs
// leaves none of them behind.
#ifndef SLAM_DATASETS_ATOMIC_FILE_H_
#define SLAM_DATASETS_ATOMIC_FILE_H_

#include <string>
#include <string_view>
#include <vector>

namespace slam {

// Writes `contents` to `path` atomically (see above). On failure returns
// false, sets *error to "PATH: problem" and leaves PATH untouched and no
// temporary file.
bool WriteFileAtomically(const std::string& path, std::string_view contents,
                         std::string* error);

// Checks, before any work, that WriteFileAtomically can write `path`: not a
// directory, its folder exists, and a file can be created there (a
// temporary is created and removed). False with "PATH: problem".
bool CheckOutputFile(const std::string& path, std::string* error);

// Creates `dir` and its missing parents (0755). With a current OutputStage
// the folders created are removed again (if empty) when the stage is
// discarded or on a fatal signal (see above). False with "DIR: problem".
bool CreateOutputFolder(const std::string& dir, std::string* error);

// The outputs of one command, published together by Commit. Stages nest
// (the innermost one collects); one thread's stage does not see the writes
// of another thread.
class OutputStage {
 public:
  OutputStage();
  ~OutputStage();
  OutputStage(const OutputStage&) = delete;
  OutputStage& operator=(const OutputStage&) = delete;

  // Renames every staged temporary over its target, in the order written.
  // False (with "PATH: problem") if a rename fails; the temporaries not yet
  // renamed are removed.
  bool Commit(std::string* error);

  // Used by WriteFileAtomically: a complete temporary for `target`. A second
  // write of the same target replaces the first. `release` forgets the
  // temporary in the signal cleanup list of the code that created it.
  struct Pending {
    std::string temp;
    std::string target;
    void (*release)(int slot) = nullptr;
    int slot = -1;
  };
  void Add(Pending pending);
  // Used by CreateOutputFolder: a folder it created (kept by Commit,
  // removed if empty otherwise).
  struct Folder {
    std::string path;
    void (*release)(int slot) = nullptr;
    int slot = -1;
  };
  void AddFolder(Folder folder);
  // Removes the folders added (innermost first, only empty ones) now.
  void RemoveFolders();

  // The innermost stage of this thread, or nullptr.
  static OutputStage* Current();
  // Makes `stage` the current one of this thread (for code loaded as a
  // separate module, e.g. the plot module, which has its own copy of this
  // file: apps/plot_module.cc hands it the caller's stage).
  static void SetCurrent(OutputStage* stage);

 private:
  void Discard();

  std::vector<Pending> pending_;
  std::vector<Folder> folders_;
  OutputStage* previous_;
};

}  // namespace slam

#endif  // SLAM_DATASETS_ATOMIC_FILE_H_
