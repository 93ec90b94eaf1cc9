#include "datasets/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace slam {
namespace {

constexpr char kTempMarker[] = ".slam-tmp-";
constexpr int kMaxSymlinkHops = 40;

// ---------------------------------------------------------------------------
// Temporaries to remove on a fatal signal. Process-wide by nature (a signal
// handler has no other way to find them): fixed slots, so that the handler
// only reads memory and calls unlink (async-signal-safe).

constexpr int kSlots = 256;
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

struct Slot {
  std::atomic<bool> used{false};
  bool folder = false;  // A folder created for the outputs: rmdir.
  char path[PATH_MAX];
};

Slot g_slots[kSlots];
struct sigaction g_previous[sizeof(kSignals) / sizeof(kSignals[0])];

void RemoveTempsOnSignal(int sig) {
  for (Slot& slot : g_slots) {
    if (slot.used.load(std::memory_order_acquire) && !slot.folder) {
      ::unlink(slot.path);
    }
  }
  // Then the folders created for the outputs, if empty now (nested ones
  // first: a pass per level, at most as many as there are slots).
  for (int pass = 0; pass < kSlots; ++pass) {
    bool removed = false;
    for (Slot& slot : g_slots) {
      if (slot.used.load(std::memory_order_acquire) && slot.folder &&
          ::rmdir(slot.path) == 0) {
        slot.used.store(false, std::memory_order_release);
        removed = true;
      }
    }
    if (!removed) break;
  }
  // Die (or go on) as the signal's previous disposition says.
  for (size_t i = 0; i < sizeof(kSignals) / sizeof(kSignals[0]); ++i) {
    if (kSignals[i] == sig) ::sigaction(sig, &g_previous[i], nullptr);
  }
  ::raise(sig);
}

void InstallSignalHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (size_t i = 0; i < sizeof(kSignals) / sizeof(kSignals[0]); ++i) {
      struct sigaction action {};
      action.sa_handler = RemoveTempsOnSignal;
      sigemptyset(&action.sa_mask);
      action.sa_flags = SA_RESETHAND;
      struct sigaction previous {};
      if (::sigaction(kSignals[i], nullptr, &previous) != 0) continue;
      // An ignored signal (nohup) stays ignored.
      if (previous.sa_handler == SIG_IGN) continue;
      g_previous[i] = previous;
      ::sigaction(kSignals[i], &action, nullptr);
    }
  });
}

// A slot for `path`, or -1 when all are taken (the temporary is then only
// cleaned up by a later write, see RemoveStaleTemps).
int RegisterTemp(const std::string& path, bool folder = false) {
  InstallSignalHandlers();
  if (path.size() >= PATH_MAX) return -1;
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (!g_slots[i].used.load(std::memory_order_relaxed)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].folder = folder;
      g_slots[i].used.store(true, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void ReleaseTemp(int slot) {
  if (slot >= 0 && slot < kSlots) {
    g_slots[slot].used.store(false, std::memory_order_release);
  }
}

// ---------------------------------------------------------------------------

thread_local OutputStage* t_current_stage = nullptr;

std::string DirName(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string BaseName(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Follows symbolic links from `path` to the file they finally name (which
// may not exist). False with *err set on a loop or a read error.
bool FollowSymlinks(const std::string& path, std::string* target,
                    struct stat* st, bool* exists, int* err) {
  std::string current = path;
  for (int hop = 0; hop <= kMaxSymlinkHops; ++hop) {
    if (::lstat(current.c_str(), st) != 0) {
      if (errno != ENOENT) {
        *err = errno;
        return false;
      }
      *exists = false;
      *target = current;
      return true;
    }
    if (!S_ISLNK(st->st_mode)) {
      *exists = true;
      *target = current;
      return true;
    }
    char buffer[PATH_MAX];
    const ssize_t n = ::readlink(current.c_str(), buffer, sizeof(buffer) - 1);
    if (n < 0) {
      *err = errno;
      return false;
    }
    const std::string link(buffer, static_cast<size_t>(n));
    current = (!link.empty() && link[0] == '/') ? link
                                                : DirName(current) + "/" + link;
  }
  *err = ELOOP;
  return false;
}

// Removes PATH.slam-tmp-PID-XXXXXX files whose process is gone (left by a
// process killed with SIGKILL).
void RemoveStaleTemps(const std::string& target) {
  const std::string dir = DirName(target);
  const std::string prefix = BaseName(target) + kTempMarker;
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return;
  while (const dirent* entry = ::readdir(d)) {
    const std::string name = entry->d_name;
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || *end != '-' || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      ::unlink((dir + "/" + name).c_str());
    }
  }
  ::closedir(d);
}

bool WriteAll(int fd, std::string_view contents, int* err) {
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n =
        ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      *err = errno;
      return false;
    }
    written += static_cast<size_t>(n);
  }
  return true;
}

// Writes into an existing file that is not a regular one (/dev/null, a FIFO,
// a device): it must not be replaced.
bool WriteDirectly(const std::string& path, const std::string& target,
                   std::string_view contents, std::string* error) {
  const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
  int err = 0;
  if (fd < 0) {
    *error = path + ": cannot open for writing: " + std::strerror(errno);
    return false;
  }
  const bool ok = WriteAll(fd, contents, &err);
  if (::close(fd) != 0 && ok) err = errno;
  if (!ok || err != 0) {
    *error = path + ": cannot write: " + std::strerror(err);
    return false;
  }
  return true;
}

void SyncDirectory(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// The file an output path names (symbolic links followed): *exists and
// *st when it exists. False ("PATH: problem") on a link loop or a folder.
bool ResolveOutput(const std::string& path, std::string* target,
                   struct stat* st, bool* exists, std::string* error) {
  int err = 0;
  if (!FollowSymlinks(path, target, st, exists, &err)) {
    *error = path + ": cannot resolve the path: " + std::strerror(err);
    return false;
  }
  if (*exists && S_ISDIR(st->st_mode)) {
    *error = path + ": is a directory";
    return false;
  }
  return true;
}

}  // namespace

bool WriteFileAtomically(const std::string& path, std::string_view contents,
                         std::string* error) {
  std::string target;
  struct stat st;
  bool exists = false;
  int err = 0;
  if (!ResolveOutput(path, &target, &st, &exists, error)) return false;
  if (exists && !S_ISREG(st.st_mode)) {
    return WriteDirectly(path, target, contents, error);
  }
  RemoveStaleTemps(target);
  std::string tmp =
      target + kTempMarker + std::to_string(::getpid()) + "-XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    *error = path + ": cannot create a temporary file: " + std::strerror(errno);
    return false;
  }
  const int slot = RegisterTemp(tmp);
  auto fail = [&](const std::string& what, int code) {
    ::unlink(tmp.c_str());
    ReleaseTemp(slot);
    *error = path + ": " + what + ": " + std::strerror(code);
    return false;
  };
  // mkstemp creates the file 0600; give it the mode of the file it replaces,
  // or the usual 0644.
  ::fchmod(fd, exists ? (st.st_mode & 07777) : 0644);
  if (!WriteAll(fd, contents, &err)) {
    ::close(fd);
    return fail("cannot write " + tmp, err);
  }
  // The data must be on disk before the rename makes it the file.
  if (::fsync(fd) != 0 && errno != EINVAL) {
    err = errno;
    ::close(fd);
    return fail("cannot flush " + tmp, err);
  }
  if (::close(fd) != 0) return fail("cannot close " + tmp, errno);
  if (OutputStage* stage = OutputStage::Current()) {
    stage->Add({tmp, target, &ReleaseTemp, slot});
    return true;
  }
  if (::rename(tmp.c_str(), target.c_str()) != 0) {
    return fail("cannot rename " + tmp, errno);
  }
  ReleaseTemp(slot);
  SyncDirectory(DirName(target));
  return true;
}

bool CheckOutputFile(const std::string& path, std::string* error) {
  std::string target;
  struct stat st;
  bool exists = false;
  if (!ResolveOutput(path, &target, &st, &exists, error)) return false;
  if (exists && !S_ISREG(st.st_mode)) return true;  // Written directly.
  const std::string dir = DirName(target);
  struct stat dir_st;
  if (::stat(dir.c_str(), &dir_st) != 0 || !S_ISDIR(dir_st.st_mode)) {
    *error = path + ": the folder " + dir + " does not exist";
    return false;
  }
  // The way the file will be written: a temporary beside it.
  std::string probe =
      target + kTempMarker + std::to_string(::getpid()) + "-XXXXXX";
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) {
    *error = path + ": cannot write in " + dir + ": " + std::strerror(errno);
    return false;
  }
  ::close(fd);
  ::unlink(probe.c_str());
  return true;
}

bool CreateOutputFolder(const std::string& dir, std::string* error) {
  if (dir.empty()) {
    *error = "an empty output folder name";
    return false;
  }
  // Missing components, outermost first.
  std::vector<std::string> missing;
  std::string current = dir;
  while (current.size() > 1 && current.back() == '/') current.pop_back();
  struct stat st;
  while (::stat(current.c_str(), &st) != 0) {
    if (errno != ENOENT) {
      *error = dir + ": cannot create the folder: " + std::strerror(errno);
      return false;
    }
    missing.push_back(current);
    const std::string parent = DirName(current);
    if (parent == current) break;
    current = parent;
  }
  if (missing.empty() && !S_ISDIR(st.st_mode)) {
    *error = dir + ": cannot create the folder: " + std::strerror(ENOTDIR);
    return false;
  }
  OutputStage* stage = OutputStage::Current();
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0755) != 0 && errno != EEXIST) {
      *error = dir + ": cannot create the folder " + *it + ": " +
               std::strerror(errno);
      if (stage != nullptr) stage->RemoveFolders();
      return false;
    }
    if (stage != nullptr) {
      stage->AddFolder({*it, &ReleaseTemp, RegisterTemp(*it, true)});
    }
  }
  return true;
}

OutputStage::OutputStage() : previous_(t_current_stage) {
  t_current_stage = this;
}

OutputStage::~OutputStage() {
  Discard();
  t_current_stage = previous_;
}

OutputStage* OutputStage::Current() { return t_current_stage; }

void OutputStage::SetCurrent(OutputStage* stage) { t_current_stage = stage; }

void OutputStage::Add(Pending pending) {
  for (Pending& p : pending_) {
    if (p.target == pending.target) {
      ::unlink(p.temp.c_str());
      if (p.release != nullptr) p.release(p.slot);
      p = std::move(pending);
      return;
    }
  }
  pending_.push_back(std::move(pending));
}

void OutputStage::AddFolder(Folder folder) {
  folders_.push_back(std::move(folder));
}

void OutputStage::RemoveFolders() {
  // Innermost first; a folder that holds anything stays.
  for (auto it = folders_.rbegin(); it != folders_.rend(); ++it) {
    ::rmdir(it->path.c_str());
    if (it->release != nullptr) it->release(it->slot);
  }
  folders_.clear();
}

bool OutputStage::Commit(std::string* error) {
  for (const Folder& f : folders_) {
    if (f.release != nullptr) f.release(f.slot);
  }
  folders_.clear();
  std::vector<Pending> pending;
  pending.swap(pending_);
  for (size_t i = 0; i < pending.size(); ++i) {
    const Pending& p = pending[i];
    if (::rename(p.temp.c_str(), p.target.c_str()) != 0) {
      *error =
          p.target + ": cannot rename " + p.temp + ": " + std::strerror(errno);
      pending_.assign(pending.begin() + i, pending.end());
      Discard();
      return false;
    }
    if (p.release != nullptr) p.release(p.slot);
    SyncDirectory(DirName(p.target));
  }
  return true;
}

void OutputStage::Discard() {
  for (const Pending& p : pending_) {
    ::unlink(p.temp.c_str());
    if (p.release != nullptr) p.release(p.slot);
  }
  pending_.clear();
  RemoveFolders();
}

}  // namespace slam
