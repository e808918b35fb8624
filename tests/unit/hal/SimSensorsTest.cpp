#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <memory>

#include "hal/sim/SimDevices.hpp"

namespace carril::hal {
namespace {

// SimCamera holds a 3.7 MB frame on the heap; the object itself is small.
TEST(SimDevicesCameraTest, NoFrameBeforePublish) {
  SimCamera cam;
  EXPECT_EQ(cam.latest(), nullptr);
}

TEST(SimDevicesCameraTest, PublishedFramesHaveIncreasingSeq) {
  SimCamera cam;
  cam.back_buffer().width = 640;
  cam.back_buffer().height = 480;
  cam.back_buffer().pixel(10, 20)[2] = 200;
  cam.publish(1'000);
  const CameraFrame* f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->seq, 1U);
  EXPECT_EQ(f->stamp_ns, 1'000);
  EXPECT_EQ(f->width, 640);
  EXPECT_EQ(f->height, 480);
  EXPECT_EQ(f->pixel(10, 20)[2], 200);
  cam.publish(2'000);
  f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->seq, 2U);
  EXPECT_EQ(f->stamp_ns, 2'000);
  // Reading again without a publish gives the same frame.
  EXPECT_EQ(cam.latest()->seq, 2U);
}

TEST(SimDevicesCameraTest, SilentFaultDeliversNothing) {
  SimCamera cam;
  cam.publish(1'000);
  ASSERT_NE(cam.latest(), nullptr);
  cam.inject_fault(SimSensorFault::Silent);
  EXPECT_EQ(cam.latest(), nullptr);
  cam.publish(2'000);  // dropped
  EXPECT_EQ(cam.latest(), nullptr);
  cam.inject_fault(SimSensorFault::None);
  cam.publish(3'000);
  const CameraFrame* f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->seq, 2U);  // the silent publish did not count
  EXPECT_EQ(f->stamp_ns, 3'000);
}

TEST(SimDevicesCameraTest, SilentBeforeFirstFrame) {
  SimCamera cam;
  cam.inject_fault(SimSensorFault::Silent);
  cam.publish(1'000);
  EXPECT_EQ(cam.latest(), nullptr);
}

TEST(SimDevicesCameraTest, WrongSizeHalvesFrame) {
  SimCamera cam;
  cam.inject_fault(SimSensorFault::WrongSize);
  cam.back_buffer().width = 640;
  cam.back_buffer().height = 480;
  cam.publish(1'000);
  const CameraFrame* f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->width, 320);
  EXPECT_EQ(f->height, 240);
  EXPECT_EQ(f->seq, 1U);
  // The renderer writes the configured size into the back buffer every frame.
  cam.back_buffer().width = 640;
  cam.back_buffer().height = 480;
  cam.inject_fault(SimSensorFault::None);
  cam.publish(2'000);
  EXPECT_EQ(cam.latest()->width, 640);
  EXPECT_EQ(cam.latest()->height, 480);
}

TEST(SimDevicesScannerTest, NoScanBeforePublish) {
  SimRangeScanner scanner;
  EXPECT_EQ(scanner.latest(), nullptr);
}

TEST(SimDevicesScannerTest, PublishedScansHaveIncreasingSeq) {
  SimRangeScanner scanner;
  LaserScan& s = scanner.back_buffer();
  s.count = 3;
  s.ranges_m[0] = 1.0F;
  s.ranges_m[1] = 2.0F;
  s.ranges_m[2] = 3.0F;
  scanner.publish(5'000);
  const LaserScan* got = scanner.latest();
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(got->seq, 1U);
  EXPECT_EQ(got->stamp_ns, 5'000);
  EXPECT_EQ(got->count, 3);
  EXPECT_EQ(got->ranges_m[1], 2.0F);
  scanner.publish(6'000);
  EXPECT_EQ(scanner.latest()->seq, 2U);
  EXPECT_EQ(scanner.latest()->stamp_ns, 6'000);
}

TEST(SimDevicesScannerTest, SilentFaultDeliversNothing) {
  SimRangeScanner scanner;
  scanner.publish(1'000);
  scanner.inject_fault(SimSensorFault::Silent);
  EXPECT_EQ(scanner.latest(), nullptr);
  scanner.publish(2'000);
  scanner.inject_fault(SimSensorFault::None);
  ASSERT_NE(scanner.latest(), nullptr);
  EXPECT_EQ(scanner.latest()->seq, 1U);
  EXPECT_EQ(scanner.latest()->stamp_ns, 1'000);
}

TEST(SimDevicesScannerTest, WrongSizeDoesNotApply) {
  SimRangeScanner scanner;
  scanner.back_buffer().count = 360;
  scanner.inject_fault(SimSensorFault::WrongSize);
  scanner.publish(1'000);
  ASSERT_NE(scanner.latest(), nullptr);
  EXPECT_EQ(scanner.latest()->count, 360);
}

TEST(SimDevicesImuTest, PublishAndSilentFault) {
  SimImu imu;
  EXPECT_FALSE(imu.read().valid);
  ImuSample s;
  s.stamp_ns = 42;
  s.valid = true;
  s.yaw_rate_radps = 0.25F;
  imu.publish(s);
  EXPECT_TRUE(imu.read().valid);
  EXPECT_EQ(imu.read().stamp_ns, 42);
  EXPECT_EQ(imu.read().yaw_rate_radps, 0.25F);
  imu.inject_fault(SimSensorFault::Silent);
  EXPECT_FALSE(imu.read().valid);
  EXPECT_EQ(imu.read().stamp_ns, 0);
  imu.inject_fault(SimSensorFault::None);
  EXPECT_TRUE(imu.read().valid);
}

TEST(SimDevicesCameraTest, BlankFaultPublishesOneFlatColour) {
  SimCamera cam;
  cam.back_buffer().width = 64;
  cam.back_buffer().height = 48;
  cam.back_buffer().pixel(10, 20)[1] = 200;
  cam.inject_fault(SimSensorFault::Blank);
  cam.publish(1'000);
  const CameraFrame* f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->seq, 1U);  // still on time
  for (int v = 0; v < 48; ++v) {
    for (int u = 0; u < 64; ++u) ASSERT_EQ(f->pixel(u, v)[1], 0) << u << "," << v;
  }
}

TEST(SimDevicesCameraTest, FrozenFaultRepeatsTheLastImageWithFreshStamps) {
  SimCamera cam;
  cam.back_buffer().width = 64;
  cam.back_buffer().height = 48;
  cam.back_buffer().pixel(3, 4)[0] = 77;
  cam.inject_fault(SimSensorFault::Frozen);
  cam.publish(1'000);
  cam.back_buffer().pixel(3, 4)[0] = 99;  // the scene changes ...
  cam.publish(2'000);
  const CameraFrame* f = cam.latest();
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->seq, 2U);
  EXPECT_EQ(f->stamp_ns, 2'000);
  EXPECT_EQ(f->pixel(3, 4)[0], 77);  // ... the image does not
  cam.inject_fault(SimSensorFault::None);
  cam.back_buffer().pixel(3, 4)[0] = 99;
  cam.publish(3'000);
  EXPECT_EQ(cam.latest()->pixel(3, 4)[0], 99);
}

// The back buffer is vouched for as the renderer left it only after a publish that did not write
// into it or resize it: none before the first, none after a blank, frozen or resized frame.
TEST(SimDevicesCameraTest, BackBufferAsRenderedOnlyAfterPublishesThatLeaveIt) {
  SimCamera cam;
  cam.back_buffer().width = 64;
  cam.back_buffer().height = 48;
  EXPECT_FALSE(cam.back_buffer_as_rendered());
  const SimSensorFault faults[] = {SimSensorFault::None,   SimSensorFault::Silent,
                                   SimSensorFault::Blank,  SimSensorFault::None,
                                   SimSensorFault::Frozen, SimSensorFault::WrongSize,
                                   SimSensorFault::None};
  const bool expected[] = {true, true, false, true, false, false, true};
  for (std::size_t i = 0; i < std::size(faults); ++i) {
    cam.back_buffer().width = 64;  // as a renderer sets them
    cam.back_buffer().height = 48;
    cam.inject_fault(faults[i]);
    cam.publish(TimeNs(1'000 * (i + 1)));
    EXPECT_EQ(cam.back_buffer_as_rendered(), expected[i]) << i;
  }
}

class SimDevicesScannerGarbage : public testing::TestWithParam<SimSensorFault> {};

TEST_P(SimDevicesScannerGarbage, EveryRangeReplacedScansStillOnTime) {
  SimRangeScanner scanner;
  LaserScan& b = scanner.back_buffer();
  b.count = 100;
  b.range_min_m = 0.05F;
  b.range_max_m = 8.0F;
  for (int i = 0; i < 100; ++i) b.ranges_m[std::size_t(i)] = 2.0F;
  scanner.inject_fault(GetParam());
  scanner.publish(1'000);
  const LaserScan* s = scanner.latest();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->seq, 1U);
  for (int i = 0; i < 100; ++i) {
    const float r = s->ranges_m[std::size_t(i)];
    const bool valid = std::isfinite(r) && r > 0.0F && r >= s->range_min_m && r <= s->range_max_m;
    ASSERT_FALSE(valid) << i << ": " << r;
  }
}

INSTANTIATE_TEST_SUITE_P(Fault, SimDevicesScannerGarbage,
                         testing::Values(SimSensorFault::NanRanges, SimSensorFault::ZeroRanges,
                                         SimSensorFault::OutOfLimitRanges));

TEST(SimDevicesImuTest, FrozenRepeatsTheSampleStampAndAll) {
  SimImu imu;
  ImuSample s;
  s.valid = true;
  s.stamp_ns = 1;
  s.yaw_rate_radps = 0.1F;
  imu.publish(s);
  imu.inject_fault(SimSensorFault::Frozen);
  s.stamp_ns = 2;
  s.yaw_rate_radps = 0.7F;
  imu.publish(s);
  EXPECT_EQ(imu.read().stamp_ns, 1);
  EXPECT_EQ(imu.read().yaw_rate_radps, 0.1F);
  EXPECT_TRUE(imu.read().valid);
}

TEST(SimDevicesImuTest, OutOfRangeReadsImplausibleValues) {
  SimImu imu;
  ImuSample s;
  s.valid = true;
  s.stamp_ns = 5;
  imu.inject_fault(SimSensorFault::OutOfRange);
  imu.publish(s);
  EXPECT_EQ(imu.read().stamp_ns, 5);
  EXPECT_TRUE(std::isnan(imu.read().roll_rad));
  EXPECT_GT(imu.read().yaw_rate_radps, 100.0F);
}

TEST(SimDevicesClockTest, SleepJumpsForwardNeverBack) {
  SimClock clock;
  EXPECT_EQ(clock.now_ns(), 0);
  clock.sleep_until_ns(10'000'000);
  EXPECT_EQ(clock.now_ns(), 10'000'000);
  clock.sleep_until_ns(5'000'000);  // already past: no change
  EXPECT_EQ(clock.now_ns(), 10'000'000);
  clock.sleep_until_ns(10'000'000);
  EXPECT_EQ(clock.now_ns(), 10'000'000);
  clock.set_now_ns(30'000'000);
  EXPECT_EQ(clock.now_ns(), 30'000'000);
  clock.sleep_until_ns(20'000'000);
  EXPECT_EQ(clock.now_ns(), 30'000'000);
}

TEST(SimDevicesClockTest, CpuTimeIsRealAndMonotonic) {
  SimClock clock;
  const TimeNs a = clock.cpu_now_ns();
  clock.sleep_until_ns(1'000'000'000'000);  // a simulated jump does not move compute time
  const TimeNs b = clock.cpu_now_ns();
  EXPECT_GE(b, a);
  EXPECT_LT(b - a, 1'000'000'000);  // far less than the simulated 1000 s
  EXPECT_GT(a, 0);
}

}  // namespace
}  // namespace carril::hal
