// Outputs and temporaries (issue 46, item 7): a symlink planted at an output's name is refused,
// never followed; an existing file is never reused; files get the umask's mode; a leftover
// FILE.part of our own from a killed run is replaced.
#include "loader/SafeCreate.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "loader/AtomicWrite.hpp"

namespace carril::loader {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class SafeCreateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::path(::testing::TempDir()) / ("safe_create_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    victim = dir / "victim";
    std::ofstream(victim) << "precious";
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir, victim;
};

TEST_F(SafeCreateTest, ASymlinkPlantedAtTheOutputIsRefusedAndItsTargetUntouched) {
  const fs::path part = dir / "can.log.part";
  fs::create_symlink(victim, part);
  std::string error;
  EXPECT_EQ(open_new_output(part.string(), error), nullptr);
  EXPECT_NE(error.find("not a regular file is there (a symlink?): refused"), std::string::npos)
      << error;
  EXPECT_EQ(slurp(victim), "precious");
  EXPECT_LT(create_exclusive(part.string(), error), 0);  // O_EXCL | O_NOFOLLOW on its own too
  EXPECT_NE(error.find("already there: nothing is overwritten"), std::string::npos) << error;
  EXPECT_EQ(slurp(victim), "precious");
}

TEST_F(SafeCreateTest, ALeftoverPartOfOursIsReplacedByANewFile) {
  const fs::path part = dir / "can.log.part";
  std::ofstream(part) << "old run";
  std::string error;
  std::FILE* f = open_new_output(part.string(), error);
  ASSERT_NE(f, nullptr) << error;
  std::fputs("new", f);
  std::fclose(f);
  EXPECT_EQ(slurp(part), "new");
}

TEST_F(SafeCreateTest, FilesGetTheUmasksMode) {
  const mode_t old = ::umask(027);
  std::string error;
  std::FILE* f = open_new_output((dir / "out").string(), error);
  ASSERT_NE(f, nullptr) << error;
  std::fclose(f);
  EXPECT_FALSE(write_file_atomically((dir / "atomic").string(), "x").has_value());
  ::umask(old);
  struct stat st {};
  ASSERT_EQ(::stat((dir / "out").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640U);
  ASSERT_EQ(::stat((dir / "atomic").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640U);
}

TEST_F(SafeCreateTest, AnAtomicWriteOverASymlinkReplacesTheLinkNotItsTarget) {
  const fs::path out = dir / "map.yaml";
  fs::create_symlink(victim, out);
  EXPECT_FALSE(write_file_atomically(out.string(), "new map").has_value());
  EXPECT_EQ(slurp(victim), "precious");
  EXPECT_FALSE(fs::is_symlink(out));
  EXPECT_EQ(slurp(out), "new map");
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace carril::loader
