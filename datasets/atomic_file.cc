#include "datasets/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <unistd.h>

namespace slam {

bool WriteFileAtomically(const std::string& path, const std::string& content,
                         std::string* error) {
  const std::string tmp =
      path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) {
    *error = path + ": cannot write (" + std::strerror(errno) + ")";
    return false;
  }
  const bool written =
      std::fwrite(content.data(), 1, content.size(), file) == content.size();
  const bool flushed = std::fflush(file) == 0;
  const bool closed = std::fclose(file) == 0;
  if (!written || !flushed || !closed) {
    *error = path + ": write failed (" + std::strerror(errno) + ")";
    std::remove(tmp.c_str());
    return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    *error = path + ": cannot rename the temporary file (" + ec.message() + ")";
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace slam
