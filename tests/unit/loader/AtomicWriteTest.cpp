// Atomic file replacement: complete content, no temporary file left, and an existing file is
// replaced (a new inode) only once the new content is complete.
#include "loader/AtomicWrite.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include "tests/unit/loader/MapFileTestUtil.hpp"

namespace carril::loader {
namespace {

using test::fresh_dir;
using test::list_dir;
using test::read_bytes;
using test::write_bytes;

TEST(AtomicWrite, WritesTheBytesAndLeavesNoTemporaryFile) {
  const auto dir = fresh_dir();
  const std::string bytes("binary\0data\xff", 12);
  ASSERT_EQ(write_file_atomically((dir / "map.bin").string(), bytes), std::nullopt);
  EXPECT_EQ(read_bytes(dir / "map.bin"), bytes);
  EXPECT_EQ(list_dir(dir), std::vector<std::string>{"map.bin"});
}

TEST(AtomicWrite, ReplacesAnExistingFileByRename) {
  const auto dir = fresh_dir();
  const auto path = dir / "map.bin";
  write_bytes(path, "old content");
  // A reader that opened the old file keeps reading the old file: it was renamed over, not
  // rewritten in place.
  const int fd = ::open(path.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(write_file_atomically(path.string(), "new"), std::nullopt);
  char buf[32] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf, 0);
  ::close(fd);
  EXPECT_EQ(std::string(buf, static_cast<std::size_t>(n)), "old content");
  EXPECT_EQ(read_bytes(path), "new");
  EXPECT_EQ(list_dir(dir), std::vector<std::string>{"map.bin"});
}

TEST(AtomicWrite, AFailedWriteLeavesTheOldFileAndNoTemporaryFile) {
  const auto dir = fresh_dir();
  const auto path = dir / "map.bin";
  write_bytes(path, "old content");
  // A file size limit makes write() fail part way (EFBIG), like a full disk.
  struct sigaction ignore = {}, previous = {};
  ignore.sa_handler = SIG_IGN;
  ASSERT_EQ(::sigaction(SIGXFSZ, &ignore, &previous), 0);
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  rlimit small = old_limit;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const auto error = write_file_atomically(path.string(), std::string(100000, 'x'));
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  ::sigaction(SIGXFSZ, &previous, nullptr);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->rfind(path.string() + ": cannot write ", 0), 0U) << *error;
  EXPECT_NE(error->find("File too large"), std::string::npos) << *error;
  EXPECT_EQ(read_bytes(path), "old content");
  EXPECT_EQ(list_dir(dir), std::vector<std::string>{"map.bin"});
}

TEST(AtomicWrite, MissingDirectoryIsNamed) {
  const auto dir = fresh_dir();
  const std::string path = (dir / "no_such_dir" / "map.bin").string();
  const auto error = write_file_atomically(path, "x");
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->rfind(path + ": cannot create a temporary file in ", 0), 0U) << *error;
  EXPECT_NE(error->find("No such file or directory"), std::string::npos) << *error;
}

}  // namespace
}  // namespace carril::loader
