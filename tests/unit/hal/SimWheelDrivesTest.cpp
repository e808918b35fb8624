#include <gtest/gtest.h>

#include "hal/sim/SimDevices.hpp"

namespace carril::hal {
namespace {

class SimWheelDrivesTest : public ::testing::Test {
 protected:
  void expect_all(DriveState s) const {
    for (int i = 0; i < drives.count(); ++i) EXPECT_EQ(drives.state(i), s) << "wheel " << i;
  }
  // One bus sync, then what the simulator hands the motors (by reference).
  const float* sync() {
    drives.sync();
    return take();
  }
  // What the motors are asked for, without a sync.
  const float* take() {
    for (float& t : target) t = -99.0F;  // poison: every wheel must be written
    drives.take_setpoints(target);
    return target;
  }
  void enable_fully() {
    drives.enable();
    sync();
    sync();
  }

  SimWheelDrives drives{4};
  float target[kMaxWheels] = {};
  const float setpoint[4] = {1.0F, -2.0F, 3.5F, 4.25F};
};

TEST_F(SimWheelDrivesTest, StartsDisabled) {
  EXPECT_EQ(drives.count(), 4);
  expect_all(DriveState::Disabled);
  WheelFeedbackSet fb;
  drives.read(fb);
  EXPECT_EQ(fb.count, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(fb.wheel[i].state, DriveState::Disabled);
    EXPECT_EQ(fb.wheel[i].fault, DriveFault::None);
  }
  EXPECT_EQ(drives.quick_stop_requests(), 0);
}

TEST_F(SimWheelDrivesTest, EnableTakesOneSync) {
  drives.enable();
  expect_all(DriveState::Disabled);  // requests take effect at the bus sync
  sync();
  expect_all(DriveState::Enabling);
  sync();
  expect_all(DriveState::Enabled);
  sync();
  expect_all(DriveState::Enabled);
}

TEST_F(SimWheelDrivesTest, SetpointsPassOnlyWhenEnabled) {
  drives.set_velocity(setpoint, 4);
  const float* t = sync();  // Disabled
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  drives.enable();
  t = sync();  // Enabling
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  t = sync();  // Enabled
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], setpoint[i]) << i;
  const float stop[4] = {0.0F, 0.0F, -1.0F, 0.0F};
  drives.set_velocity(stop, 4);
  t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], stop[i]) << i;
}

TEST_F(SimWheelDrivesTest, DisableZeroesTargets) {
  enable_fully();
  drives.set_velocity(setpoint, 4);
  drives.disable();
  expect_all(DriveState::Disabled);
  const float* t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  expect_all(DriveState::Disabled);  // and stays there without a new enable
}

TEST_F(SimWheelDrivesTest, QuickStopLatchesAndIsCounted) {
  enable_fully();
  drives.set_velocity(setpoint, 4);
  drives.quick_stop();
  expect_all(DriveState::QuickStop);
  EXPECT_EQ(drives.quick_stop_requests(), 1);
  const float* t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  sync();
  expect_all(DriveState::QuickStop);  // latched: no automatic recovery
  drives.set_velocity(setpoint, 4);   // ignored while stopped
  t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  drives.quick_stop();
  EXPECT_EQ(drives.quick_stop_requests(), 2);
  // enable() leaves quick stop through the normal sequence.
  drives.enable();
  sync();
  expect_all(DriveState::Enabling);
  t = sync();
  expect_all(DriveState::Enabled);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], setpoint[i]) << i;
}

TEST_F(SimWheelDrivesTest, FaultLatchesThroughEnable) {
  enable_fully();
  drives.set_velocity(setpoint, 4);
  drives.inject_fault(2, DriveFault::Overcurrent);
  EXPECT_EQ(drives.state(2), DriveState::Fault);
  WheelFeedbackSet fb;
  drives.read(fb);
  EXPECT_EQ(fb.wheel[2].state, DriveState::Fault);
  EXPECT_EQ(fb.wheel[2].fault, DriveFault::Overcurrent);
  EXPECT_EQ(static_cast<std::uint16_t>(fb.wheel[2].fault), 0x2310);
  EXPECT_EQ(fb.wheel[0].fault, DriveFault::None);

  drives.enable();
  sync();
  sync();
  const float* t = sync();
  EXPECT_EQ(drives.state(2), DriveState::Fault);
  EXPECT_EQ(t[2], 0.0F);  // a faulted drive does not follow setpoints
  EXPECT_EQ(t[0], setpoint[0]);
  // Neither disable nor quick stop clears a fault.
  drives.disable();
  drives.quick_stop();
  EXPECT_EQ(drives.state(2), DriveState::Fault);
  EXPECT_EQ(drives.state(0), DriveState::QuickStop);
}

TEST_F(SimWheelDrivesTest, ResetFaultsReturnsToDisabled) {
  drives.inject_fault(0, DriveFault::HeartbeatLost);
  drives.inject_fault(3, DriveFault::FollowingError);
  drives.reset_faults();
  expect_all(DriveState::Disabled);
  WheelFeedbackSet fb;
  drives.read(fb);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(fb.wheel[i].fault, DriveFault::None) << i;
  // Then the normal enable sequence works.
  enable_fully();
  expect_all(DriveState::Enabled);
}

TEST_F(SimWheelDrivesTest, ResetFaultsLeavesHealthyDrivesAlone) {
  enable_fully();
  drives.inject_fault(1, DriveFault::Undervoltage);
  drives.reset_faults();
  EXPECT_EQ(drives.state(0), DriveState::Enabled);
  EXPECT_EQ(drives.state(1), DriveState::Disabled);
}

TEST_F(SimWheelDrivesTest, RecoveryAfterFaultNeedsAFreshEnable) {
  // CiA 402: a fault drops the drive out of Operation enabled; after fault reset it stays
  // Disabled until the master runs the enable sequence again.
  enable_fully();
  const float sp[4] = {1, 2, 3, 4};
  drives.set_velocity(sp, 4);
  drives.inject_fault(1, DriveFault::Undervoltage);
  drives.reset_faults();
  const float* t = sync();
  t = sync();
  EXPECT_EQ(drives.state(1), DriveState::Disabled);
  EXPECT_EQ(t[1], 0.0F);
  EXPECT_EQ(t[0], 1.0F);  // the healthy drives keep running
  drives.enable();
  sync();
  t = sync();
  EXPECT_EQ(drives.state(1), DriveState::Enabled);
  EXPECT_EQ(t[1], 0.0F);  // the setpoint from before the fault was dropped with it
}

TEST_F(SimWheelDrivesTest, ReadReportsFeedback) {
  drives.set_feedback(0, 1'000, 1.5F, 12.25);
  drives.set_feedback(3, 2'000, -0.5F, -3.0);
  WheelFeedbackSet fb;
  drives.read(fb);
  EXPECT_EQ(fb.count, 4);
  EXPECT_EQ(fb.wheel[0].stamp_ns, 1'000);
  EXPECT_EQ(fb.wheel[0].velocity_radps, 1.5F);
  EXPECT_EQ(fb.wheel[0].position_rad, 12.25);
  EXPECT_EQ(fb.wheel[3].stamp_ns, 2'000);
  EXPECT_EQ(fb.wheel[3].velocity_radps, -0.5F);
  EXPECT_EQ(fb.wheel[3].position_rad, -3.0);
  EXPECT_EQ(fb.wheel[1].velocity_radps, 0.0F);
  // Feedback does not disturb the state machine and vice versa.
  EXPECT_EQ(fb.wheel[0].state, DriveState::Disabled);
  enable_fully();
  drives.read(fb);
  EXPECT_EQ(fb.wheel[0].state, DriveState::Enabled);
  EXPECT_EQ(fb.wheel[0].position_rad, 12.25);
}

TEST_F(SimWheelDrivesTest, InitIsOkAndChangesNothing) {
  const DriveInitResult r = drives.init();
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.drive, -1);
  EXPECT_STREQ(r.what, "");
  expect_all(DriveState::Disabled);  // bring-up is not an enable
  EXPECT_EQ(drives.syncs(), 0U);
}

TEST_F(SimWheelDrivesTest, InitFailureNamesTheDrive) {
  drives.fail_init(2, "drive 2 (rear-left): no boot-up within 1.0 s");
  const DriveInitResult r = drives.init();
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.drive, 2);
  EXPECT_STREQ(r.what, "drive 2 (rear-left): no boot-up within 1.0 s");
}

TEST_F(SimWheelDrivesTest, SetpointsSetButNotSyncedAreNotApplied) {
  enable_fully();
  drives.set_velocity(setpoint, 4);
  const float* t = take();  // staged only: the motors still get the last sync's zero
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], 0.0F) << i;
  t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], setpoint[i]) << i;
  const float other[4] = {-1.0F, -1.0F, -1.0F, -1.0F};
  drives.set_velocity(other, 4);
  t = take();  // the latched setpoints hold until the next sync, as on a bus
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], setpoint[i]) << i;
  t = sync();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], other[i]) << i;
}

TEST_F(SimWheelDrivesTest, OnlySyncAdvancesTheStateMachine) {
  drives.enable();
  for (int k = 0; k < 3; ++k) take();
  expect_all(DriveState::Disabled);
  EXPECT_EQ(drives.syncs(), 0U);
  sync();
  expect_all(DriveState::Enabling);
  sync();
  expect_all(DriveState::Enabled);
  EXPECT_EQ(drives.syncs(), 2U);
}

TEST_F(SimWheelDrivesTest, FaultStopsTheLatchedSetpointAtOnce) {
  enable_fully();
  drives.set_velocity(setpoint, 4);
  sync();
  drives.inject_fault(1, DriveFault::Overcurrent);
  const float* t = take();  // no sync needed: a faulted drive's bridge is off
  EXPECT_EQ(t[1], 0.0F);
  EXPECT_EQ(t[0], setpoint[0]);
  EXPECT_EQ(t[3], setpoint[3]);
}

TEST(SimWheelDrivesTwoWheelTest, TakeSetpointsWritesOnlyItsWheels) {
  SimWheelDrives drives(2);
  EXPECT_EQ(drives.count(), 2);
  const float sp[2] = {3.0F, -3.0F};
  drives.set_velocity(sp, 2);
  drives.enable();
  drives.sync();
  drives.sync();
  float target[kMaxWheels] = {7.0F, 7.0F, 7.0F, 7.0F};
  drives.take_setpoints(target);
  EXPECT_EQ(target[0], 3.0F);
  EXPECT_EQ(target[1], -3.0F);
  EXPECT_EQ(target[2], 7.0F);
  EXPECT_EQ(target[3], 7.0F);
  WheelFeedbackSet fb;
  drives.read(fb);
  EXPECT_EQ(fb.count, 2);
}

}  // namespace
}  // namespace carril::hal
