// The YAML pre-check (issue 46, item 7): yaml-cpp 0.7 lets a quoted string without its closing
// quote run on over the following lines, so a scenario's expect block vanished into a string and
// the run passed. Every carril file now gets file:line for it, whatever the parser's leniency;
// quotes inside plain scalars, comments and block scalars stay legal.
#include "loader/YamlPrecheck.hpp"

#include <gtest/gtest.h>

#include <string>

#include "loader/StrictYaml.hpp"

namespace carril::loader::strict {
namespace {

TEST(YamlPrecheckTest, AnUnterminatedQuoteIsRefusedWithItsLineAndColumn) {
  // What yaml-cpp 0.7 reads as name = "abc\nexpect: ..." with no expect block at all.
  const std::string text = "name: \"abc\nexpect:\n  result: end_reached\n";
  EXPECT_EQ(precheck_yaml(text),
            "1: invalid YAML: the double quote at column 7 is not closed on its line (a quoted "
            "string must end on the line it starts)");
  EXPECT_EQ(precheck_yaml("a: 1\nb: {x: 'it''s, y: 2}\n"),
            "2: invalid YAML: the single quote at column 8 is not closed on its line (a quoted "
            "string must end on the line it starts)");
  EXPECT_EQ(precheck_yaml("list:\n  - \"one\"\n  - \"two\n  - three\n").substr(0, 40),
            "3: invalid YAML: the double quote at col");
  EXPECT_EQ(precheck_yaml("\"key: 1\n").substr(0, 2), "1:");
  EXPECT_EQ(precheck_yaml("a: [1, \"x]\n").substr(0, 2), "1:");
}

TEST(YamlPrecheckTest, LegalQuotesCommentsAndBlockScalarsPass) {
  for (const char* ok : {
           "name: \"a \\\" b\"  # an escaped quote\n",
           "what: 'it''s'\n",
           "text: it's plain, and \"so\" is this\n",
           "url: http://x/\"y\n",  // a quote inside a plain scalar
           "# a comment with a \" quote\nkey: value # and 'another\n",
           "description: >\n  A lap \"around\n  the circle's tape.\nnext: 1\n",
           "- |\n    \"raw text\n- 'b'\n",
           "m: {what: \"ramp surface\", x: 1}\n",
           "m: {a: 1,\n  b: \"c\"}\n",
           "",
           "key:\n",
       }) {
    EXPECT_EQ(precheck_yaml(ok), "") << ok;
  }
}

TEST(YamlPrecheckTest, AfterABlockScalarTheCheckResumes) {
  EXPECT_EQ(precheck_yaml("description: >\n  text \"here\nname: \"open\n").substr(0, 2), "3:");
}

TEST(YamlPrecheckTest, EveryLoaderRefusesItWithFileAndLine) {
  const std::string file = "scenario.yaml";
  try {
    parse_document("name: x\nwhat: \"unterminated\nexpect: {result: end_reached}\n", &file);
    FAIL() << "accepted";
  } catch (const LoadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("scenario.yaml:2: invalid YAML: the double quote", 0), 0U)
        << e.what();
  }
}

}  // namespace
}  // namespace carril::loader::strict
