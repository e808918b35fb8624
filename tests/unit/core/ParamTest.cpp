// Settings tables: validate() checks every row's range with its unit, in table order, and reads
// integer and real members alike.
#include "firmware/core/Param.hpp"

#include <gtest/gtest.h>

#include <string>

namespace carril::fw {
namespace {

struct Cfg {
  double gain = 2.0;
  int frames = 3;
  static std::span<const Param<Cfg>> params() {
    static constexpr Param<Cfg> kParams[] = {
        CARRIL_PARAM(Cfg, gain, "1/s", 0.5, 10.0, "how hard it pulls"),
        CARRIL_PARAM(Cfg, frames, "frames", 1, 100, "how long it waits", nullptr, false),
    };
    return kParams;
  }
  Status validate() const { return Checks("cfg").params(*this, params()).result(); }
};

TEST(Param, RowsNameTheirMemberAndReadIt) {
  const auto rows = Cfg::params();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_STREQ(rows[0].info.name, "gain");
  EXPECT_FALSE(rows[0].is_integer());
  EXPECT_TRUE(rows[0].info.tunable);
  EXPECT_STREQ(rows[1].info.name, "frames");
  EXPECT_TRUE(rows[1].is_integer());
  EXPECT_FALSE(rows[1].info.tunable);
  Cfg c;
  EXPECT_EQ(rows[0].get(c), 2.0);
  EXPECT_EQ(rows[1].get(c), 3.0);
  rows[1].set(c, 42.0);
  rows[0].set(c, 0.75);
  EXPECT_EQ(c.frames, 42);
  EXPECT_EQ(c.gain, 0.75);
}

TEST(Param, ValidateChecksEveryRowInOrder) {
  Cfg c;
  EXPECT_TRUE(c.validate().is_ok());
  c.gain = 10.0;  // bounds are inclusive
  c.frames = 1;
  EXPECT_TRUE(c.validate().is_ok());
  c.frames = 0;
  EXPECT_EQ(std::string(c.validate().message()), "cfg.frames: 0 frames, expected 1 to 100 frames");
  c.gain = 0.4;  // the first row's failure is the one reported
  EXPECT_EQ(std::string(c.validate().message()), "cfg.gain: 0.4 1/s, expected 0.5 to 10 1/s");
  c.gain = __builtin_nan("");
  EXPECT_EQ(std::string(c.validate().message()), "cfg.gain: nan 1/s, expected 0.5 to 10 1/s");
}

}  // namespace
}  // namespace carril::fw
