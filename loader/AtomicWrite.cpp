#include "loader/AtomicWrite.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "loader/SafeCreate.hpp"

namespace carril::loader {

namespace {

std::string errno_text(int err) {
  return std::strerror(err);
}

// Closes the descriptor and removes the temporary file unless released (the rename succeeded).
class TempFile {
 public:
  TempFile(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!released_) ::unlink(path_.c_str());
  }
  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  // Closes now, for the error of close() itself (a delayed write error on NFS shows up there).
  int close_now() {
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc;
  }
  void release() { released_ = true; }

 private:
  int fd_;
  std::string path_;
  bool released_ = false;
};

}  // namespace

std::optional<std::string> write_file_atomically(const std::string& path, std::string_view bytes) {
  const std::filesystem::path target(path);
  const std::filesystem::path dir =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  // A fresh name in the same directory (same filesystem, so rename is atomic), created without
  // following symlinks and with the umask's mode.
  std::string tmp_path, error;
  const int fd = create_temp_beside(path, tmp_path, error);
  if (fd < 0) return error;
  TempFile tmp(fd, tmp_path);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(tmp.fd(), bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return path + ": cannot write " + tmp.path() + ": " + errno_text(errno);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(tmp.fd()) != 0) {
    return path + ": cannot fsync " + tmp.path() + ": " + errno_text(errno);
  }
  if (tmp.close_now() != 0) {
    return path + ": cannot close " + tmp.path() + ": " + errno_text(errno);
  }
  if (::rename(tmp.path().c_str(), path.c_str()) != 0) {
    return path + ": cannot rename " + tmp.path() + " over it: " + errno_text(errno);
  }
  tmp.release();
  // The rename is durable only once the directory entry is on disk.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return path + ": cannot open directory " + dir.string() + ": " + errno_text(errno);
  const int rc = ::fsync(dfd);
  const int err = errno;
  ::close(dfd);
  if (rc != 0) return path + ": cannot fsync directory " + dir.string() + ": " + errno_text(err);
  return std::nullopt;
}

}  // namespace carril::loader
