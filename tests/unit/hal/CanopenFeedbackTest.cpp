// The master's watchdog on the drives' feedback (issue 46, item 5): TPDOs that are malformed,
// missing or implausible (a speed no wheel reaches, a position that jumps) for
// feedback_missed_syncs SYNC periods in a row latch a drive fault that quick-stops every drive,
// as a lost heartbeat does; fewer bad periods are counted and ride through; an implausible
// reading is never handed to the firmware.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "CanopenTestBench.hpp"
#include "hal/canopen/CanopenWheelDrives.hpp"

namespace carril::hal::canopen::test {
namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

class CanopenFeedback : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(b.up_and_enabled()) << b.drives().bring_up_result().what;
    const float sp[2] = {2.0F, 2.0F};
    b.drives().set_velocity(sp, 2);
    b.ticks(10);
    ASSERT_EQ(b.drives().counters().feedback_bad, 0U);
  }
  // Both drives are quick-stopped by the master from now on.
  bool every_drive_stopped() {
    return b.feedback(0).state != DriveState::Enabled &&
           b.feedback(1).state != DriveState::Enabled && b.slave(2).rpdos.back().target == 0 &&
           b.slave(3).rpdos.back().target == 0;
  }

  Bench b;
  const int n = Bench::default_config().feedback_missed_syncs;
};

TEST_F(CanopenFeedback, MalformedFeedbackForTheConfiguredPeriodsFaultsAndStopsEveryDrive) {
  b.slave(3).short_tpdo1 = 1000;
  b.ticks(n - 1);  // one period short of the limit: counted, still driving
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
  EXPECT_EQ(b.drives().counters().faults, 0U);
  b.ticks(2);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(1).fault), kFaultFeedback);
  b.ticks(2);
  EXPECT_TRUE(every_drive_stopped());
  const std::string why = b.drives().last_fault();
  EXPECT_TRUE(contains(
      why, "drive 1 (node 3): feedback bad for " + std::to_string(n) + " SYNC periods in a row"))
      << why;
  EXPECT_TRUE(contains(why, "TPDO1 malformed")) << why;
  EXPECT_GE(b.drives().counters().malformed, std::uint64_t(n));
}

TEST_F(CanopenFeedback, AFewBadPeriodsAreCountedAndRideThrough) {
  b.slave(3).short_tpdo1 = n - 2;
  b.ticks(3 * n);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
  EXPECT_EQ(b.drives().counters().faults, 0U);
  EXPECT_EQ(b.drives().counters().feedback_bad, std::uint64_t(n - 2));
}

TEST_F(CanopenFeedback, MissingPositionFaultsAndNamesWhatIsMissing) {
  b.slave(2).no_tpdo2 = true;
  b.ticks(n + 2);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(0).fault), kFaultFeedback);
  EXPECT_TRUE(contains(b.drives().last_fault(), "no TPDO2 (position)")) << b.drives().last_fault();
  b.ticks(2);
  EXPECT_TRUE(every_drive_stopped());
}

TEST_F(CanopenFeedback, ASpeedNoWheelReachesIsNeverHandedOnAndFaults) {
  const float before = b.feedback(1).velocity_radps;
  ASSERT_NEAR(before, 2.0F, 0.01F);
  b.slave(3).velocity_lie = 2'000'000'000;  // counts/s: thousands of rad/s at the wheel
  b.ticks(2);
  EXPECT_NEAR(b.feedback(1).velocity_radps, before, 0.01F);  // the stale value, not the lie
  b.ticks(n + 1);
  EXPECT_EQ(static_cast<std::uint16_t>(b.feedback(1).fault), kFaultFeedback);
  EXPECT_TRUE(contains(b.drives().last_fault(), "velocity actual beyond"))
      << b.drives().last_fault();
  EXPECT_GE(b.drives().counters().implausible, std::uint64_t(n));
}

TEST_F(CanopenFeedback, APositionJumpIsNotOdometryAndOneGlitchRidesThrough) {
  const double before = b.feedback(0).position_rad;
  b.slave(2).position_jump = 10'000'000;  // counts: 1,500 rad at the wheel in one period
  b.ticks(2);                             // the SYNC it answers, then the period that reads it
  const double after = b.feedback(0).position_rad;
  EXPECT_LT(std::abs(after - before), 0.1);  // not the jump: two periods at 2 rad/s
  EXPECT_EQ(b.drives().counters().implausible, 1U);
  b.ticks(5);
  EXPECT_GT(b.feedback(0).position_rad, after);  // odometry resumes from the new reading
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.drives().counters().faults, 0U);
}

TEST_F(CanopenFeedback, TheFaultClearsOnlyOnceTheFeedbackIsGoodAgain) {
  b.slave(3).short_tpdo1 = 1000;
  b.ticks(n + 2);
  ASSERT_EQ(b.feedback(1).state, DriveState::Fault);
  b.drives().reset_faults();  // still bad: the latch stays
  b.drives().enable();
  b.ticks(3);
  EXPECT_EQ(b.feedback(1).state, DriveState::Fault);
  b.slave(3).short_tpdo1 = 0;
  b.ticks(2);
  b.drives().reset_faults();
  b.drives().enable();
  b.ticks(10);
  EXPECT_EQ(b.feedback(0).state, DriveState::Enabled);
  EXPECT_EQ(b.feedback(1).state, DriveState::Enabled);
}

TEST(CanopenFeedbackConfig, ALimitBelowTwoPeriodsOrNoSpeedLimitIsRefused) {
  CanopenConfig c = Bench::default_config();
  c.feedback_missed_syncs = 1;
  Bench one(c);
  EXPECT_FALSE(one.drives().init().ok);
  EXPECT_TRUE(contains(one.drives().config_error(), "feedback_missed_syncs = 1"));
  c = Bench::default_config();
  c.drive[1].max_wheel_radps = std::nan("");
  Bench nan(c);
  EXPECT_FALSE(nan.drives().init().ok);
  EXPECT_TRUE(contains(nan.drives().config_error(), "drive[1].max_wheel_radps"));
}

}  // namespace
}  // namespace carril::hal::canopen::test
