// The results CSV's pieces: the summary reader flattens nested objects and lists, rejects what is
// not one JSON object; CSV fields are quoted when they must be.
#include "host_sim/campaign/Results.hpp"

#include <gtest/gtest.h>

#include <string>

namespace carril::sim::campaign {
namespace {

TEST(ResultsTest, ASummaryIsReadInOrderWithObjectsFlattened) {
  const auto f = parse_summary(
      "{\n  \"scenario\": \"circle\",\n  \"passed\": true,\n  \"sim_time_s\": 50,\n"
      "  \"end_stop_error_m\": null,\n  \"unmet_expectations\": [\"a, b\", \"c\"],\n"
      "  \"mission_counters\": {\"cells\": 48, \"deep\": {\"x\": -1.5e-3}},\n"
      "  \"note\": \"say \\\"hi\\\"\\n\"\n}\n");
  ASSERT_TRUE(f.has_value());
  ASSERT_EQ(f->size(), 8u);
  EXPECT_EQ((*f)[0], std::make_pair(std::string("scenario"), std::string("circle")));
  EXPECT_EQ((*f)[1].second, "true");
  EXPECT_EQ((*f)[2].second, "50");
  EXPECT_EQ((*f)[3].second, "");
  EXPECT_EQ((*f)[4].second, "a, b;c");
  EXPECT_EQ((*f)[5].first, "mission_counters.cells");
  EXPECT_EQ((*f)[6].first, "mission_counters.deep.x");
  EXPECT_EQ((*f)[6].second, "-1.5e-3");
  EXPECT_EQ((*f)[7].second, "say \"hi\"\n");
}

TEST(ResultsTest, WhatIsNotOneObjectIsRejected) {
  EXPECT_FALSE(parse_summary("").has_value());
  EXPECT_FALSE(parse_summary("[1, 2]").has_value());
  EXPECT_FALSE(parse_summary("{\"a\": 1").has_value());
  EXPECT_FALSE(parse_summary("{\"a\": 1} {}").has_value());
  EXPECT_FALSE(parse_summary("{\"a\" 1}").has_value());
  EXPECT_FALSE(parse_summary("{\"a\": }").has_value());
  EXPECT_FALSE(parse_summary("{\"a\": \"open}").has_value());
  EXPECT_TRUE(parse_summary(" {} ").has_value());
}

TEST(ResultsTest, CsvFieldsAreQuotedWhenTheyMustBe) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace carril::sim::campaign
