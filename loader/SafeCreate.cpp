#include "loader/SafeCreate.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace carril::loader {

int create_exclusive(const std::string& path, std::string& error) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    error = path + ": cannot create it" +
            (err == EEXIST ? std::string(" (something is already there: nothing is overwritten)")
                           : ": " + std::string(std::strerror(err)));
  }
  return fd;
}

int create_temp_beside(const std::string& target, std::string& tmp_path, std::string& error) {
  const std::filesystem::path t(target);
  const std::filesystem::path dir = t.has_parent_path() ? t.parent_path() : ".";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::uint64_t r = 0;
    if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) {
      r = (std::uint64_t(::getpid()) << 32) ^ std::uint64_t(attempt) ^ std::uint64_t(time(nullptr));
    }
    char suffix[24];
    std::snprintf(suffix, sizeof suffix, "%012llx",
                  static_cast<unsigned long long>(r & 0xFFFFFFFFFFFFULL));
    tmp_path = (dir / ("." + t.filename().string() + ".tmp." + suffix)).string();
    const int fd =
        ::open(tmp_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    if (errno != EEXIST) {
      error = target + ": cannot create a temporary file in " + dir.string() + ": " +
              std::strerror(errno);
      return -1;
    }
  }
  error = target + ": cannot create a temporary file in " + dir.string() +
          ": every name tried was taken";
  return -1;
}

bool clear_stale_output(const std::string& path, std::string& error) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return true;
    error = path + ": cannot inspect it: " + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    error = path + ": something that is not a regular file is there (a symlink?): refused";
    return false;
  }
  if (st.st_uid != ::geteuid()) {
    error =
        path + ": a file of another user (uid " + std::to_string(st.st_uid) + ") is there: refused";
    return false;
  }
  if (::unlink(path.c_str()) != 0) {
    error = path + ": cannot remove the leftover file: " + std::strerror(errno);
    return false;
  }
  return true;
}

std::FILE* open_new_output(const std::string& path, std::string& error) {
  if (!clear_stale_output(path, error)) return nullptr;
  const int fd = create_exclusive(path, error);
  if (fd < 0) return nullptr;
  std::FILE* f = ::fdopen(fd, "w");
  if (f == nullptr) {
    error = path + ": " + std::strerror(errno);
    ::close(fd);
  }
  return f;
}

}  // namespace carril::loader
