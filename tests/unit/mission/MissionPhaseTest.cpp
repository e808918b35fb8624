#include "firmware/mission/MissionPhase.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

TEST(MissionPhaseTest, AChangeIsReportedOnceAndASameNamedPhaseOnlyOnANewState) {
  static const char* const kPlan = "plan";
  static const char* const kDrive = "drive";
  MissionPhase p;
  EXPECT_STREQ(p.current(), "wait");
  EXPECT_EQ(p.take_change(), nullptr);  // nothing entered yet
  p.restart("wait");
  EXPECT_STREQ(p.take_change(), "wait");  // enter() reports where it starts
  EXPECT_EQ(p.take_change(), nullptr);    // once
  p.set(kPlan, false);
  EXPECT_EQ(p.current(), kPlan);
  EXPECT_EQ(p.take_change(), kPlan);
  p.set(kPlan, false);  // the same phase again, same state: no event
  EXPECT_EQ(p.take_change(), nullptr);
  p.set(kPlan, true);  // a new state named like the last: an event
  EXPECT_EQ(p.take_change(), kPlan);
  p.set(kDrive, false);
  p.set(kPlan, false);  // two changes between reads: the latest is reported
  EXPECT_EQ(p.take_change(), kPlan);
  EXPECT_EQ(p.current(), kPlan);
}

}  // namespace
}  // namespace carril::fw
