#include "loader/StrictYaml.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "loader/RobotLoader.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader::strict {
namespace {

// parse_document's message for `text`, or "ok".
std::string outcome(const std::string& text) {
  static const std::string file = "f.yaml";
  try {
    parse_document(text, &file);
    return "ok";
  } catch (const LoadError& e) {
    return e.what();
  }
}

// Runs `text` through parse_document in a child process that an alarm ends after 10 s, so a
// parser that never returns fails the test instead of hanging it (and growing without bound).
// The child prints the outcome and exits 0.
void expect_returns(const std::string& text, const std::string& message_regex) {
  EXPECT_EXIT(
      {
        alarm(10);
        std::fprintf(stderr, "%s\n", outcome(text).c_str());
        std::exit(0);
      },
      ::testing::ExitedWithCode(0), message_regex)
      << text.substr(0, 80);
}

// Found by fuzzing (tests/fuzz/*/regressions/stray_comma_hang): a ',' outside [ ] or { } made
// yaml-cpp 0.7's LoadAll hand out empty documents forever (jbeder/yaml-cpp#1040), and every
// carril file is read through parse_document. Now one message names the line and column.
TEST(StrictYamlDeathTest, AStrayCommaIsAnErrorNotAHang) {
  expect_returns(",", "f.yaml:1: invalid YAML: unexpected ',' at column 1");
  expect_returns("a: 1\n,\n", "f.yaml:2: invalid YAML");
  expect_returns("# comment\n\n  ,", "f.yaml:3: invalid YAML: unexpected ',' at column 3");
  // The inputs the fuzzers found, exactly (the occupancy map's: its YAML part).
  for (const char* target : {"robot", "controller", "mission", "occupancy_map", "scenario"}) {
    std::string text = test::read_text(
        test::source_path(std::string("tests/fuzz/") + target + "/regressions/stray_comma_hang"));
    ASSERT_FALSE(text.empty()) << target;
    text = text.substr(0, text.find("\n%%PGM%%\n"));
    expect_returns(text, "f.yaml:[0-9]+: invalid YAML");
  }
}

TEST(StrictYamlDeathTest, TheRobotLoaderNamesTheFileOfAStrayComma) {
  EXPECT_EXIT(
      {
        alarm(10);
        RobotSpec r;
        std::string error;
        const std::string path = test::source_path("tests/fuzz/robot/regressions/stray_comma_hang");
        const bool ok = load_robot_preset(path, r, error);
        std::fprintf(stderr, "%s\n", error.c_str());
        std::exit(ok ? 1 : 0);
      },
      ::testing::ExitedWithCode(0), "stray_comma_hang:3: invalid YAML: unexpected ','");
}

// A map path in a mission reached /etc/shadow, and the message printed its first line. A file
// of another kind is named and what was expected said, never its bytes.
TEST(StrictYaml, AFileOfAnotherKindIsNamedButNeverEchoed) {
  const std::string file = "shadow";
  auto error_of = [&](const std::string& text) {
    try {
      parse_document(text, &file).expect_map({"image", "resolution"});
      return std::string("accepted");
    } catch (const LoadError& e) {
      return std::string(e.what());
    }
  };
  const std::string keys = error_of("root:$6$s3cretHash:19000:0:99999:7:::\ndaemon:*:1::\n");
  EXPECT_EQ(keys,
            "shadow:1: (top level): expected a map of keys (image, resolution), got a key of 36 "
            "bytes that is not a name (is this the right file?)");
  EXPECT_EQ(keys.find("s3cret"), std::string::npos);
  const std::string scalar = error_of("s3cret line of text\n");
  EXPECT_EQ(scalar,
            "shadow:1: (top level): expected a map, got a single value of 19 bytes (is this the "
            "right file?)");
  // A misspelt key of the right kind of file is still named: that is the user's own text.
  EXPECT_EQ(error_of("imge: m.pgm\n").find("shadow:1: imge: unknown key"), 0U);
}

TEST(StrictYaml, AFileOverTheSizeBoundIsRefusedBeforeParsing) {
  const std::string big = ::testing::TempDir() + "/big.yaml";
  {
    std::FILE* f = std::fopen(big.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fseek(f, long(kMaxYamlBytes), SEEK_SET), 0);  // sparse: no disk used
    std::fputc('\n', f);
    std::fclose(f);
  }
  try {
    read_file(big);
    FAIL() << "read";
  } catch (const LoadError& e) {
    EXPECT_EQ(std::string(e.what()), big +
                                         ": 4194305 bytes, more than the 4194304 a carril YAML "
                                         "file may have");
  }
  std::filesystem::remove(big);
}

TEST(StrictYaml, DocumentsAreCountedAsBefore) {
  EXPECT_EQ(outcome("a: 1\n"), "ok");
  EXPECT_EQ(outcome("---\na: 1\n...\n"), "ok");
  EXPECT_EQ(outcome("[1, 2]\n"), "ok");
  EXPECT_EQ(outcome("{a: 1, b: 2}\n"), "ok");
  EXPECT_NE(outcome("").find("expected a map, got an empty file"), std::string::npos);
  EXPECT_NE(outcome("a: 1\n---\nb: 2\n").find("expected one YAML document, got 2 documents"),
            std::string::npos);
  EXPECT_NE(outcome("---\n---\n---\n").find("got 3 documents"), std::string::npos);
}

}  // namespace
}  // namespace carril::loader::strict
