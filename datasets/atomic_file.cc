#include "datasets/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace slam {

bool WriteFileAtomically(const std::string& path, std::string_view contents,
                         std::string* error) {
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    *error = path + ": cannot create a temporary file: " + std::strerror(errno);
    return false;
  }
  auto fail = [&](const std::string& what, int err) {
    ::unlink(tmp.c_str());
    *error = path + ": " + what + ": " + std::strerror(err);
    return false;
  };
  // mkstemp creates the file 0600; give it the mode of the file it replaces,
  // or the usual 0644.
  struct stat st;
  const mode_t mode = (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode))
                          ? (st.st_mode & 07777)
                          : 0644;
  ::fchmod(fd, mode);
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n =
        ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      return fail("cannot write " + tmp, err);
    }
    written += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) return fail("cannot close " + tmp, errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    return fail("cannot rename " + tmp, errno);
  }
  return true;
}

}  // namespace slam
