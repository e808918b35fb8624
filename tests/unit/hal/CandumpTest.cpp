// The candump log format: exact lines as can-utils writes them, read back bit for bit, and
// malformed lines refused.
#include "hal/can/Candump.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace carril::hal {
namespace {

std::string line_of(const CanFrame& f, TimeNs t) {
  char buf[kCandumpMaxLine + 1];
  const std::size_t n = format_candump(f, t, "vcan0", buf, sizeof buf);
  EXPECT_GT(n, 0U);
  return std::string(buf, n);
}

TEST(CandumpTest, LinesAsCandumpWritesThem) {
  CanFrame f;
  f.id = 0x44C;
  f.len = 2;
  f.data[0] = 0x44;
  f.data[1] = 0xA1;
  EXPECT_EQ(line_of(f, 1436509052249713000), "(1436509052.249713) vcan0 44C#44A1");
  CanFrame sync;
  sync.id = 0x080;
  EXPECT_EQ(line_of(sync, 5'000'001'000), "(5.000001) vcan0 080#");
  CanFrame ext;
  ext.id = 0x1ABCDEF0;
  ext.extended = true;
  ext.len = 1;
  ext.data[0] = 0x0F;
  EXPECT_EQ(line_of(ext, 0), "(0.000000) vcan0 1ABCDEF0#0F");
  CanFrame rtr;
  rtr.id = 0x701;
  rtr.rtr = true;
  rtr.len = 1;
  EXPECT_EQ(line_of(rtr, 0), "(0.000000) vcan0 701#R1");
  CanFrame err;
  err.error = true;
  err.id = kCanErrBusOff;
  err.len = 8;
  EXPECT_EQ(line_of(err, 0), "(0.000000) vcan0 20000040#0000000000000000");
  char tiny[10];
  EXPECT_EQ(format_candump(f, 0, "vcan0", tiny, sizeof tiny), 0U);  // too small: nothing
}

TEST(CandumpTest, ReadsBackWhatItWrites) {
  std::mt19937 rng(5);
  for (int i = 0; i < 500; ++i) {
    CanFrame f;
    f.extended = rng() % 3 == 0;
    f.error = !f.extended && rng() % 20 == 0;
    f.rtr = !f.error && rng() % 10 == 0;
    f.id = f.extended || f.error ? rng() & kCanExtIdMask : rng() & kCanStdIdMask;
    f.len = std::uint8_t(rng() % 9);
    if (!f.rtr) {
      for (int b = 0; b < f.len; ++b) f.data[b] = std::uint8_t(rng());
    }
    const TimeNs t = TimeNs(rng()) * 1000;  // whole microseconds
    CanFrame g;
    TimeNs u = 0;
    ASSERT_TRUE(parse_candump(line_of(f, t).c_str(), g, u)) << line_of(f, t);
    EXPECT_EQ(u, t);
    EXPECT_EQ(g.id, f.id) << line_of(f, t);
    EXPECT_EQ(g.extended, f.extended);
    EXPECT_EQ(g.error, f.error);
    EXPECT_EQ(g.rtr, f.rtr);
    EXPECT_EQ(g.len, f.len);
    for (int b = 0; b < f.len && !f.rtr; ++b) EXPECT_EQ(g.data[b], f.data[b]);
  }
}

TEST(CandumpTest, MalformedLinesAreRefused) {
  CanFrame f;
  f.id = 0x123;
  TimeNs t = 7;
  for (const char* bad : {"", "vcan0 123#00", "(1.0) vcan0 123-00", "(1.000000) vcan0 12#00",
                          "(1.000000) vcan0 1234#00", "(1.000000) vcan0 800#00",
                          "(1.000000) vcan0 12G#00", "(1.000000) vcan0 123#0",
                          "(1.000000) vcan0 123#001122334455667788", "(1.000000) vcan0 123#00ZZ"}) {
    EXPECT_FALSE(parse_candump(bad, f, t)) << bad;
  }
  EXPECT_EQ(f.id, 0x123U);  // untouched
  EXPECT_EQ(t, 7);
}

// Found by fuzzing (tests/fuzz/candump/regressions/stamp_overflow): seconds beyond what TimeNs
// holds overflowed the nanoseconds (signed overflow, UB). The stamp is now read digit by digit:
// no sign, a ')' after it, at most the year 2262.
TEST(CandumpTest, StampsOutsideTimeNsOrMalformedAreRefused) {
  CanFrame f;
  f.id = 0x123;
  TimeNs t = 7;
  for (const char* bad :
       {"(170000000000000.5) can0 20000040#0000000000000000", "(9223372036.000000) vcan0 123#00",
        "(-1.000000) vcan0 123#00", "(+1.000000) vcan0 123#00", "(1.000000 vcan0 123#00",
        "(1.0000001) vcan0 123#00", "(.000001) vcan0 123#00", "(1.) vcan0 123#00"}) {
    EXPECT_FALSE(parse_candump(bad, f, t)) << bad;
  }
  EXPECT_EQ(f.id, 0x123U);  // untouched
  EXPECT_EQ(t, 7);
  ASSERT_TRUE(parse_candump("(9223372035.999999) vcan0 123#00", f, t));
  EXPECT_EQ(t, TimeNs{9'223'372'035'999'999'000});
  ASSERT_TRUE(parse_candump(" (1.5) vcan0 123#00", f, t));  // microseconds, as can-utils reads
  EXPECT_EQ(t, TimeNs{1'000'005'000});
}

}  // namespace
}  // namespace carril::hal
