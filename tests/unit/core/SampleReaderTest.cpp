// SampleReader: each consumer takes each new device sample once, by the driver's sequence number.
#include "firmware/core/SampleReader.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace carril::fw {
namespace {

struct Sample {
  std::uint32_t seq = 0;
};

TEST(SampleReader, TakesEachSequenceOnceAndNeverSequenceZero) {
  SampleReader<Sample> r;
  Sample s;
  EXPECT_EQ(r.take(nullptr), nullptr);
  EXPECT_EQ(r.take(&s), nullptr);  // seq 0: the driver has nothing yet
  EXPECT_FALSE(r.ever());
  s.seq = 1;
  EXPECT_TRUE(r.fresh(&s));
  EXPECT_EQ(r.take(&s), &s);
  EXPECT_TRUE(r.ever());
  EXPECT_FALSE(r.fresh(&s));
  EXPECT_EQ(r.take(&s), nullptr);  // the same scan again, next tick
  s.seq = 2;
  EXPECT_EQ(r.take(&s), &s);
  s.seq = 0;  // a driver that restarts: nothing until its first new sample
  EXPECT_EQ(r.take(&s), nullptr);
  EXPECT_TRUE(r.ever());
}

TEST(SampleReader, ConsumersDoNotHideSamplesFromEachOther) {
  SampleReader<Sample> a, b;
  Sample s{7};
  EXPECT_EQ(a.take(&s), &s);
  EXPECT_EQ(b.take(&s), &s);
  EXPECT_EQ(a.take(&s), nullptr);
  // A consumer that waits (the localiser while its filter is busy) takes the newest later.
  s.seq = 8;
  s.seq = 9;
  EXPECT_EQ(b.take(&s), &s);
  EXPECT_FALSE(b.fresh(&s));
}

}  // namespace
}  // namespace carril::fw
