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
