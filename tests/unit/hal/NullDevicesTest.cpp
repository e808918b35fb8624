#include <gtest/gtest.h>

#include "hal/null/NullDevices.hpp"

namespace carril::hal {
namespace {

TEST(NullWheelDrivesTest, InitIsOk) {
  NullWheelDrives drives(4);
  const DriveInitResult r = drives.init();
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.drive, -1);
  EXPECT_STREQ(r.what, "");
}

TEST(NullWheelDrivesTest, SyncedCommandsMoveNothing) {
  NullWheelDrives drives(4);
  const float sp[4] = {1.0F, 2.0F, 3.0F, 4.0F};
  drives.enable();
  for (int k = 0; k < 3; ++k) {
    drives.set_velocity(sp, 4);
    drives.sync();
  }
  WheelFeedbackSet fb;
  fb.wheel[0].velocity_radps = 9.0F;  // poison: read must overwrite
  drives.read(fb);
  EXPECT_EQ(fb.count, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(fb.wheel[i].state, DriveState::Disabled) << i;  // never enables
    EXPECT_EQ(fb.wheel[i].velocity_radps, 0.0F) << i;
    EXPECT_EQ(fb.wheel[i].fault, DriveFault::None) << i;
  }
}

TEST(NullDevicesTest, SensorsReportNothing) {
  NullCamera camera;
  NullRangeScanner scanner;
  NullImu imu;
  EXPECT_EQ(camera.latest(), nullptr);
  EXPECT_EQ(scanner.latest(), nullptr);
  EXPECT_FALSE(imu.read().valid);
}

}  // namespace
}  // namespace carril::hal
