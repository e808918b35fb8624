// report_state: the map missions' one state-to-status rule.
#include "firmware/mission/MissionStates.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

enum class S : std::uint8_t { Wait, Drive, Done, Failed };

TEST(MissionStates, WaitStartsAndWaitsTheEndsAreTheirOwnAndTheRestRuns) {
  MissionPhase phase;
  phase.restart("wait");
  MissionState m = report_state(S::Wait, "WAIT", phase, MissionStatus::Active);
  EXPECT_EQ(m.status, MissionStatus::Starting);
  EXPECT_TRUE(m.waiting);
  EXPECT_EQ(m.id, 0);
  EXPECT_STREQ(m.name, "WAIT");
  EXPECT_STREQ(m.phase, "wait");
  phase.set("track", true);
  m = report_state(S::Drive, "DRIVE", phase, MissionStatus::Finishing, true);
  EXPECT_EQ(m.status, MissionStatus::Finishing);
  EXPECT_FALSE(m.waiting);
  EXPECT_TRUE(m.on_path);
  EXPECT_EQ(m.id, 1);
  EXPECT_STREQ(m.phase, "track");
  EXPECT_EQ(report_state(S::Drive, "DRIVE", phase, MissionStatus::Active).status,
            MissionStatus::Active);
  EXPECT_EQ(report_state(S::Done, "DONE", phase, MissionStatus::Active).status,
            MissionStatus::Done);
  EXPECT_EQ(report_state(S::Failed, "FAILED", phase, MissionStatus::Active).status,
            MissionStatus::Failed);
  EXPECT_EQ(fault_output(Fault::NoPath).fault, Fault::NoPath);
}

}  // namespace
}  // namespace carril::fw
